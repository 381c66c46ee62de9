// NFF cone or cylinder `c`: base centre and radius, apex centre and radius,
// no end caps. Negative radii mean the inside is the visible side.
#pragma once
#include "box.h"

namespace rt {

struct Cone {
    Vec3 base;
    double baseRadius;   // >= 0 (absolute value of the file's)
    Vec3 apex;
    double apexRadius;   // >= 0
    bool insideVisible;  // radii negative in the file
    // Derived by finish():
    Vec3 axis;       // unit vector base -> apex
    double height;   // |apex - base|
    double slope;    // radius change per unit height
    Box box;

    bool finish();  // false when base == apex or both radii are zero
    Box bounds() const { return box; }
    double intersect(const Ray& r, double lo, double hi, bool twoSided) const;
    Vec3 normal(const Vec3& p) const;  // unit, towards the visible side

private:
    Vec3 outwardNormal(const Vec3& p) const;
};

}  // namespace rt
