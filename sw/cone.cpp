#include "cone.h"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace rt {

bool Cone::finish() {
    const Vec3 w = apex - base;
    height = glm::length(w);
    if (!(height > 0) || !(baseRadius > 0 || apexRadius > 0)) return false;
    axis = w / height;
    slope = (apexRadius - baseRadius) / height;
    // Bounds of the two end discs: a disc of radius r with unit normal a
    // extends r * sqrt(1 - a_k^2) along axis k.
    box = Box{};
    for (int end = 0; end < 2; ++end) {
        const Vec3 c = end ? apex : base;
        const double rad = end ? apexRadius : baseRadius;
        const Vec3 e = rad * glm::sqrt(glm::max(Vec3(0.0), Vec3(1.0) - axis * axis));
        box.add(c - e);
        box.add(c + e);
    }
    return true;
}

Vec3 Cone::outwardNormal(const Vec3& p) const {
    // Surface |q| = r(s) with s along the axis and q the radial part; its
    // gradient is q/|q| - slope * axis.
    const Vec3 rel = p - base;
    const Vec3 q = rel - glm::dot(rel, axis) * axis;
    return glm::normalize(glm::normalize(q) - slope * axis);
}

Vec3 Cone::normal(const Vec3& p) const {
    const Vec3 n = outwardNormal(p);
    return insideVisible ? -n : n;
}

double Cone::intersect(const Ray& r, double lo, double hi, bool twoSided) const {
    constexpr double none = std::numeric_limits<double>::infinity();
    // Ray in the cone's frame: s(t) = so + t sd along the axis, q(t) = qo + t qd
    // radially; the surface is |q(t)|^2 = (rb + slope s(t))^2 with 0 <= s <= h.
    const Vec3 oc = r.o - base;
    const double so = glm::dot(oc, axis), sd = glm::dot(r.d, axis);
    const Vec3 qo = oc - so * axis, qd = r.d - sd * axis;
    const double ro = baseRadius + slope * so;  // radius at the origin's height
    const double a = glm::dot(qd, qd) - slope * slope * sd * sd;
    const double b = glm::dot(qo, qd) - slope * ro * sd;
    const double c = glm::dot(qo, qo) - ro * ro;
    double roots[2];
    int count = 0;
    if (a == 0) {
        if (b == 0) return none;
        roots[count++] = -c / (2 * b);
    } else {
        const double disc = b * b - a * c;
        if (disc < 0) return none;
        const double s = std::sqrt(disc);
        double t1 = (-b - s) / a, t2 = (-b + s) / a;
        if (t1 > t2) std::swap(t1, t2);
        roots[count++] = t1;
        roots[count++] = t2;
    }
    for (int i = 0; i < count; ++i) {
        const double t = roots[i];
        if (!(lo <= t && t < hi)) continue;
        const double s = so + t * sd;
        if (s < 0 || s > height) continue;
        if (baseRadius + slope * s < 0) continue;  // the mirrored nappe of a cone
        if (!twoSided) {
            const double facing = glm::dot(r.d, outwardNormal(r.at(t)));
            if (insideVisible ? facing < 0 : facing > 0) continue;  // back side; grazing (0) counts
        }
        return t;
    }
    return none;
}

}  // namespace rt
