#include "scene.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace rt {

Box Scene::objectBounds() const {
    Box b;
    for (const Shape& s : objects) b.add(s.bounds());
    return b;
}

Box Scene::worldBox() const {
    Box b = objectBounds();
    if (!declaredBounds.empty()) b.add(declaredBounds);
    if (b.empty()) b = Box{Vec3(-1.0), Vec3(1.0)};
    // Padded by 1e-4 of its size, and of at least a millionth of its
    // distance from the origin: a scene flat along an axis far from the
    // origin (a polygon in the plane x = 1e9) is still a box whose planes
    // are apart in doubles.
    const double size = std::max({b.maxExtent(), 1e-6, 1e-6 * glm::length(b.lo), 1e-6 * glm::length(b.hi)});
    return b.expanded(1e-4 * size);
}

double Scene::rayEpsilon() const { return roundingMargin(worldBox()); }

ViewFault viewFault(const Vec3& from, const Vec3& at, const Vec3& up) {
    const Vec3 dir = at - from;
    if (glm::length(dir) == 0) return ViewFault::EyeAtTarget;
    if (glm::length(up) == 0) return ViewFault::ZeroUp;
    if (glm::length(glm::cross(dir, up)) <= 1e-12 * glm::length(dir) * glm::length(up)) return ViewFault::UpAlongView;
    return ViewFault::None;
}

}  // namespace rt
