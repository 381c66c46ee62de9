#include "shape.h"

namespace rt {

const char* primitiveName(PrimitiveKind k) {
    switch (k) {
        case PrimitiveKind::Sphere: return "sphere";
        case PrimitiveKind::Polygon: return "polygon";
        case PrimitiveKind::Cone: return "cone";
    }
    return "?";
}

Box Shape::bounds() const {
    return std::visit([](const auto& g) { return g.bounds(); }, geometry);
}

double Shape::intersect(const Ray& r, double lo, double hi) const {
    return std::visit([&](const auto& g) { return g.intersect(r, lo, hi, twoSided); }, geometry);
}

Vec3 Shape::normal(const Vec3& p) const {
    if (const auto* s = std::get_if<Sphere>(&geometry)) return s->normal(p);
    if (const auto* c = std::get_if<Cone>(&geometry)) return c->normal(p);
    return std::get<Polygon>(geometry).normal();
}

}  // namespace rt
