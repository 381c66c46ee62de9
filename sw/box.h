// Axis-aligned box with closed bounds (used for object bounds and regions).
#pragma once
#include <algorithm>
#include <limits>

#include "ray.h"

namespace rt {

struct Box {
    Vec3 lo{std::numeric_limits<double>::infinity()};
    Vec3 hi{-std::numeric_limits<double>::infinity()};

    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    Vec3 extent() const { return hi - lo; }
    double maxExtent() const {
        Vec3 e = extent();
        return std::max({e.x, e.y, e.z});
    }
    void add(const Vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void add(const Box& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    Box expanded(double margin) const { return Box{lo - Vec3(margin), hi + Vec3(margin)}; }
    // Closed overlap: boxes that only touch do overlap.
    bool overlaps(const Box& b) const {
        return lo.x <= b.hi.x && b.lo.x <= hi.x && lo.y <= b.hi.y && b.lo.y <= hi.y && lo.z <= b.hi.z &&
               b.lo.z <= hi.z;
    }
};

// A length far above the rounding error of coordinates in and around box b
// (1e-9 of its size or distance from the origin), far below any feature of a
// scene: the margin by which object bounds are widened before overlap tests,
// and the distance a spawned ray skips so as not to hit the surface it leaves.
inline double roundingMargin(const Box& b) {
    return 1e-9 * std::max({b.maxExtent(), glm::length(b.lo), glm::length(b.hi)});
}

}  // namespace rt
