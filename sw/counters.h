// Operation counters: what a node's processing cost is charged from, and what
// the reference renderer reports.
#pragma once
#include <array>
#include <cstdint>

#include "shape.h"

namespace rt {

struct Counters {
    uint64_t primaryRays = 0, primaryHits = 0;
    uint64_t shadowRays = 0, shadowHits = 0;        // shadow hit = blocked
    uint64_t secondaryRays = 0, secondaryHits = 0;  // reflected + refracted
    std::array<uint64_t, kPrimitiveKinds> tests{};  // intersection tests by primitive
    uint64_t voxelSteps = 0;                        // voxels visited by the DDA
    uint64_t shadings = 0;                          // hits shaded
    uint64_t contributions = 0;                     // pixel contributions emitted

    uint64_t intersectionTests() const { return tests[0] + tests[1] + tests[2]; }
    uint64_t rays() const { return primaryRays + shadowRays + secondaryRays; }
    Counters& operator+=(const Counters& o);
};

}  // namespace rt
