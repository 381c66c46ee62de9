// One object of a scene: a primitive, its material and its global id. The id
// breaks ties between hits at equal t, so that every partition of the scene
// picks the same object.
#pragma once
#include <cstdint>
#include <variant>

#include "cone.h"
#include "polygon.h"
#include "sphere.h"

namespace rt {

enum class PrimitiveKind : int { Sphere = 0, Polygon = 1, Cone = 2 };
constexpr int kPrimitiveKinds = 3;
const char* primitiveName(PrimitiveKind k);

struct Shape {
    std::variant<Sphere, Polygon, Cone> geometry;
    uint32_t material = 0;
    uint32_t id = 0;        // position in the scene's object list
    bool twoSided = false;  // NFF: objects are one-sided unless transparent

    PrimitiveKind kind() const { return PrimitiveKind(geometry.index()); }
    Box bounds() const;
    double intersect(const Ray& r, double lo, double hi) const;
    Vec3 normal(const Vec3& p) const;  // unit, towards the visible side
};

}  // namespace rt
