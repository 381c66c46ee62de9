// A ray in flight: what a node receives, traces through its box and forwards.
// Shading is forward (no recursion on a stack): each ray carries what it will
// add to its pixel, and where in the pixel's ray tree it sits (its path).
#pragma once
#include <cstdint>

#include "ray.h"

namespace rt {

enum class RayKind : uint8_t { Primary, Shadow, Reflected, Refracted };
const char* rayKindName(RayKind k);

// Where a contribution sits in its pixel's ray tree. path: the primary ray is
// 0, the mirror child of path p is 3p+1, the refracted child 3p+2 (bijective
// base 3, so every path is unique; 39 levels fit in 64 bits). slot: 0 for the
// ambient term of a hit or the background of a miss, 1 + i for light i.
//
// Packed to 12 bytes (4-byte aligned), so that a contribution takes 40 bytes
// instead of 48 and a ray job 136 instead of 144: the frame buffer holds
// every contribution of the frame (4.5 M on balls-5 at 1024x1024) and the
// links every ray in flight. (No references to its fields: they may be
// unaligned.)
#pragma pack(push, 4)
struct PathKey {
    uint64_t path = 0;
    uint32_t slot = 0;
    bool operator<(const PathKey& o) const { return path != o.path ? path < o.path : slot < o.slot; }
    bool operator==(const PathKey& o) const { return path == o.path && slot == o.slot; }
};
#pragma pack(pop)
static_assert(sizeof(PathKey) == 12);
constexpr int kMaxRayDepth = 39;

struct RayJob {
    Ray ray;
    double t0 = 0;    // start of the part not traced yet
    double tEnd = 0;  // where the ray stops mattering (a light's distance, or +inf)
    Vec3 weight{1.0}; // colour weight; for a shadow ray the contribution it would add
    uint32_t pixel = 0;
    PathKey key;      // slot is used by shadow rays only
    uint8_t depth = 0;
    RayKind kind = RayKind::Primary;
};

struct Contribution {
    uint32_t pixel = 0;
    PathKey key;
    Vec3 rgb{0.0};
};

}  // namespace rt
