#include "polygon.h"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace rt {

bool Polygon::finish() {
    if (vertices.size() < 3) return false;
    Vec3 newell(0.0);
    box = Box{};
    for (size_t i = 0; i < vertices.size(); ++i) {
        const Vec3& a = vertices[i];
        const Vec3& b = vertices[(i + 1) % vertices.size()];
        newell.x += (a.y - b.y) * (a.z + b.z);
        newell.y += (a.z - b.z) * (a.x + b.x);
        newell.z += (a.x - b.x) * (a.y + b.y);
        box.add(a);
    }
    const double len = glm::length(newell);
    // Collinear vertices give a (numerically) zero area; compare with the
    // square of the polygon's size so the test does not depend on units.
    const double size = box.maxExtent();
    if (!(len > 1e-12 * size * size) || !std::isfinite(len)) return false;
    n = newell / len;
    dist = glm::dot(n, vertices[0]);
    const Vec3 an = glm::abs(n);
    dropAxis = (an.x >= an.y && an.x >= an.z) ? 0 : (an.y >= an.z ? 1 : 2);
    return true;
}

bool Polygon::contains2D(const Vec3& p) const {
    // Even-odd crossing test in the plane of the two kept axes; works for
    // concave outlines. Half-open edge rule: an edge counts when one end is
    // strictly above the test line and the other is not.
    const int u = dropAxis == 0 ? 1 : 0;
    const int v = dropAxis == 2 ? 1 : 2;
    bool inside = false;
    const size_t k = vertices.size();
    for (size_t i = 0, j = k - 1; i < k; j = i++) {
        const Vec3& a = vertices[i];
        const Vec3& b = vertices[j];
        if ((a[v] > p[v]) != (b[v] > p[v])) {
            const double x = a[u] + (p[v] - a[v]) * (b[u] - a[u]) / (b[v] - a[v]);
            if (p[u] < x) inside = !inside;
        }
    }
    return inside;
}

double Polygon::intersect(const Ray& r, double lo, double hi, bool twoSided) const {
    constexpr double none = std::numeric_limits<double>::infinity();
    const double denom = glm::dot(n, r.d);
    // One-sided: only rays arriving at the front face (against the normal).
    if (denom == 0 || (!twoSided && denom > 0)) return none;
    const double t = (dist - glm::dot(n, r.o)) / denom;
    if (!(lo <= t && t < hi)) return none;
    return contains2D(r.at(t)) ? t : none;
}

}  // namespace rt
