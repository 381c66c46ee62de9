// NFF sphere `s x y z r`. A negative radius means the inside is the visible
// side (NFF); the geometric radius is |r|.
#pragma once
#include "box.h"

namespace rt {

struct Sphere {
    Vec3 centre;
    double radius;        // |r| from the file
    bool insideVisible;   // r < 0 in the file

    Box bounds() const { return Box{centre - Vec3(radius), centre + Vec3(radius)}; }
    // Nearest intersection with t in [lo, hi) on a side that may be hit
    // (both sides when twoSided), or +inf.
    double intersect(const Ray& r, double lo, double hi, bool twoSided) const;
    // Unit normal pointing to the visible side.
    Vec3 normal(const Vec3& p) const;
};

}  // namespace rt
