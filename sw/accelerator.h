// Finding the closest hit of a ray segment among one region's objects.
//
// Rule shared by every accelerator, and so by every partition of a scene: a
// hit counts if its t lies in the segment [t0, t1); among hits, the smallest
// t wins and equal t goes to the smaller object id. Intersections depend only
// on the ray and the object, never on the segment, so the same floats come
// out whichever region or voxel asks.
#pragma once
#include <algorithm>
#include <cstdint>
#include <string>
#include <limits>
#include <memory>
#include <vector>

#include "counters.h"
#include "shape.h"

namespace rt {

class Lattice;

struct Hit {
    double t = std::numeric_limits<double>::infinity();
    uint32_t object = UINT32_MAX;  // index into the region's object list
    uint32_t id = UINT32_MAX;      // the object's scene-wide id (tie-break)
    bool valid() const { return object != UINT32_MAX; }
};

// Tests each object at most once per query (Amanatides & Woo's mailbox):
// an object spanning several voxels is intersected once. One per thread.
class Mailbox {
public:
    void begin(size_t objects) {
        if (stamp_.size() < objects) stamp_.resize(objects, 0);
        if (++current_ == 0) {  // wrapped: forget every old stamp
            std::fill(stamp_.begin(), stamp_.end(), 0);
            current_ = 1;
        }
    }
    bool firstVisit(uint32_t object) {
        if (stamp_[object] == current_) return false;
        stamp_[object] = current_;
        return true;
    }

private:
    std::vector<uint32_t> stamp_;
    uint32_t current_ = 0;
};

// Intersects one object and keeps it if it beats the best hit so far.
inline void testObject(const std::vector<Shape>& objects, uint32_t index, const Ray& r, double t0, double t1,
                       Hit& best, Counters& counters) {
    const Shape& s = objects[index];
    ++counters.tests[int(s.kind())];
    const double t = s.intersect(r, t0, t1);
    if (t < best.t || (t == best.t && best.valid() && s.id < best.id)) best = Hit{t, index, s.id};
}

class Accelerator {
public:
    virtual ~Accelerator() = default;
    virtual Hit closestHit(const Ray& r, double t0, double t1, Mailbox& mailbox, Counters& counters) const = 0;
    virtual std::string describe() const = 0;
    // The cells it walks, if it is a grid (reports show each node's: a box
    // thinner than a cell tests every object across it).
    virtual const Lattice* grid() const { return nullptr; }
};

enum class AccelKind { Grid, BruteForce };

// Builds the accelerator of `kind` over `objects` (which must outlive it),
// covering `box`.
std::unique_ptr<Accelerator> makeAccelerator(AccelKind kind, const std::vector<Shape>& objects, const Box& box);

}  // namespace rt
