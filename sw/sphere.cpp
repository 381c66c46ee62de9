#include "sphere.h"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace rt {

double Sphere::intersect(const Ray& r, double lo, double hi, bool twoSided) const {
    constexpr double none = std::numeric_limits<double>::infinity();
    // |o + t d - c|^2 = radius^2  ->  a t^2 + 2 b t + c = 0
    const Vec3 oc = r.o - centre;
    const double a = glm::dot(r.d, r.d);
    const double b = glm::dot(oc, r.d);
    const double c = glm::dot(oc, oc) - radius * radius;
    const double disc = b * b - a * c;
    if (disc < 0) return none;
    const double s = std::sqrt(disc);
    const double tNear = (-b - s) / a;  // where the ray enters (outside surface)
    const double tFar = (-b + s) / a;   // where it leaves (inside surface)
    const bool nearOk = twoSided || !insideVisible;
    const bool farOk = twoSided || insideVisible;
    if (nearOk && lo <= tNear && tNear < hi) return tNear;
    if (farOk && lo <= tFar && tFar < hi) return tFar;
    return none;
}

Vec3 Sphere::normal(const Vec3& p) const {
    const Vec3 n = (p - centre) / radius;
    return insideVisible ? -n : n;
}

}  // namespace rt
