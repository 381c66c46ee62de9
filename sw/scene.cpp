#include "scene.h"

#include <algorithm>
#include <cmath>

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
    const double size = std::max(b.maxExtent(), 1e-6);
    return b.expanded(1e-4 * size);
}

double Scene::rayEpsilon() const { return roundingMargin(worldBox()); }

}  // namespace rt
