// A ray keeps its origin and direction from birth to death; nodes only
// advance the parameter interval they trace. Every plane crossing in the
// program is computed by tAt(), so two pieces of code that ask for the t of
// the same plane get the same double (this is what makes segments chain
// exactly across regions and voxels).
#pragma once
#include <glm/vec3.hpp>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace rt {

using Vec3 = glm::dvec3;

struct Ray {
    Vec3 o;    // origin
    Vec3 d;    // direction (normalised by whoever creates the ray)
    Vec3 inv;  // 1/d per component (+-inf where d is zero)

    Ray() = default;
    Ray(const Vec3& origin, const Vec3& dir) : o(origin), d(dir), inv(reciprocal(dir)) {}
    static Vec3 reciprocal(const Vec3& dir) { return Vec3(1.0 / dir.x, 1.0 / dir.y, 1.0 / dir.z); }

    Vec3 at(double t) const { return o + t * d; }
    // Parameter where the ray crosses the plane {p[axis] == coord}. Only
    // meaningful when d[axis] != 0.
    double tAt(int axis, double coord) const { return (coord - o[axis]) * inv[axis]; }
};

}  // namespace rt
