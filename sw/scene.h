// A scene as NFF describes it: view, background, lights, materials, objects.
#pragma once
#include <string>
#include <vector>

#include "shape.h"

namespace rt {

// NFF `f r g b Kd Ks Shine T ior`.
struct Material {
    Vec3 colour{1.0};
    double kd = 1.0;     // diffuse weight
    double ks = 0.0;     // specular highlight and mirror weight
    double shine = 0.0;  // Phong exponent
    double t = 0.0;      // transmittance
    double ior = 1.0;    // index of refraction (read only when t > 0)
};

// NFF `l x y z [r g b]`.
struct Light {
    Vec3 position;
    Vec3 colour{1.0};
};

// NFF viewpoint block.
struct View {
    Vec3 from, at, up;
    double angle = 45;   // degrees, between the centres of the outermost columns
    double hither = 0;   // parsed and checked; a ray tracer has no near plane
    int width = 512, height = 512;
};

// What keeps a view from being a camera, the first of: an eye at the point
// looked at, a zero `up`, an `up` along the view (within 1e-12 of
// parallel: there is no image plane). None: it is one.
enum class ViewFault { None, EyeAtTarget, ZeroUp, UpAlongView };
ViewFault viewFault(const Vec3& from, const Vec3& at, const Vec3& up);

struct Scene {
    std::string name;
    View view;
    Vec3 background{0.0};
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<Shape> objects;
    // Space the scene declares beyond its objects (the procedural scene's unit
    // cube); the world box covers both.
    Box declaredBounds;

    Box objectBounds() const;
    // The world box: bounds of the objects (and declared space), padded so
    // that no object touches a face of it.
    Box worldBox() const;
    // Smallest parameter a spawned ray starts at, relative to the scene size,
    // so that it does not hit the surface it leaves.
    double rayEpsilon() const;
};

}  // namespace rt
