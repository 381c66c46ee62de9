#include "procedural.h"

#include <random>

#include <glm/geometric.hpp>

#include "scene_error.h"

namespace rt {

void ProceduralParams::validate() const {
    auto bad = [](const std::string& what) { throw SceneError("procedural scene: " + what); };
    if (spheres < 1) bad("sphere count must be at least 1");
    if (!(radius > 0 && radius <= 0.49)) bad("sphere radius must be in (0, 0.49]");
    if (!(concentration > 0 && concentration <= 1)) bad("concentration fraction must be in (0, 1]");
    if (axis < 0 || axis > 2) bad("progress axis must be x, y or z");
    if (width < 1 || height < 1) bad("image size must be positive");
    if (!(angle > 0 && angle < 180)) bad("view angle must be in (0, 180) degrees");
    if (glm::length(lookAt - eye) == 0) bad("eye and look-at point coincide");
    if (glm::length(glm::cross(lookAt - eye, up)) == 0) bad("up vector is zero or parallel to the view");
}

Scene makeProceduralScene(const ProceduralParams& p) {
    p.validate();
    Scene s;
    s.name = "procedural";
    s.view = View{p.eye, p.lookAt, p.up, p.angle, 0.0, p.width, p.height};
    s.background = p.background;
    for (const Vec3& l : p.lights) s.lights.push_back(Light{l, Vec3(1.0)});
    s.materials = {p.material};
    // The engine is fixed by the standard (mt19937_64) and the mapping to
    // [0, 1) is ours, so the scene is the same on every platform.
    std::mt19937_64 rng(p.seed);
    auto uniform = [&] { return double(rng() >> 11) * 0x1.0p-53; };
    for (int i = 0; i < p.spheres; ++i) {
        Vec3 c(uniform(), uniform(), uniform());
        c[p.axis] *= p.concentration;
        Shape sh;
        sh.geometry = Sphere{c, p.radius, false};
        sh.material = 0;
        sh.id = uint32_t(i);
        s.objects.push_back(sh);
    }
    s.declaredBounds = Box{Vec3(0.0), Vec3(1.0)}.expanded(p.radius);
    return s;
}

}  // namespace rt
