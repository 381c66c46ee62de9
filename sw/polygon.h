// NFF polygon `p n` (or `pp n` with vertex normals): planar, convex or
// concave. The front (visible) side is the one the vertices are
// counter-clockwise from; the plane normal is Newell's, which gets that
// orientation right for concave outlines too, where the first three vertices
// may sit at a reflex corner.
#pragma once
#include <vector>

#include "box.h"

namespace rt {

struct Polygon {
    std::vector<Vec3> vertices;
    Vec3 n;        // unit normal, front side
    double dist;   // plane: dot(n, p) == dist
    int dropAxis;  // axis dropped for the 2D inside test (largest |n| component)
    Box box;

    // Builds the plane; returns false when the vertices span no plane (fewer
    // than 3 or all collinear).
    bool finish();
    Box bounds() const { return box; }
    double intersect(const Ray& r, double lo, double hi, bool twoSided) const;
    Vec3 normal() const { return n; }
    bool contains2D(const Vec3& p) const;
};

}  // namespace rt
