// The paper's experiment scene (section 4): M spheres of radius r placed
// uniformly at random in the unit cube, then their coordinate along the
// progress axis multiplied by the concentration fraction f, so they crowd
// into the first f of the space. The world box stays the unit cube (the
// scene declares it), so a uniform N x N x N split puts all spheres into the
// first ceil(f N) layers of nodes.
#pragma once
#include <cstdint>
#include <vector>

#include "scene.h"

namespace rt {

// The built-in scene's concentration on rtsim's and rtref's command lines:
// the paper's experiment on the default 4 x 4 x 4 mesh, the spheres crowded
// into the first 1/N = 1/4 of the progress axis (the same scene from both
// programs without flags: rtref's was f = 1, another image).
constexpr double kDefaultConcentration = 0.25;

struct ProceduralParams {
    int spheres = 1000;
    double radius = 0.02;
    double concentration = 1.0;  // f in (0, 1]
    int axis = 0;                // progress axis: 0 x, 1 y, 2 z
    uint64_t seed = 1;
    Vec3 eye{0.5, -1.6, 0.5};
    Vec3 lookAt{0.5, 0.5, 0.5};
    Vec3 up{0, 0, 1};
    double angle = 40;
    int width = 256, height = 256;
    // White point lights; by default two, outside the cube.
    std::vector<Vec3> lights{Vec3(-1.0, -2.0, 3.0), Vec3(2.5, -1.5, 1.5)};
    Material material{Vec3(0.9, 0.6, 0.3), 0.7, 0.3, 20.0, 0.0, 1.0};
    Vec3 background{0.078, 0.361, 0.753};

    // Throws SceneError naming the bad parameter.
    void validate() const;
};

Scene makeProceduralScene(const ProceduralParams& p);

}  // namespace rt
