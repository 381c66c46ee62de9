// Scenes the tests share.
#pragma once
#include <string>

#include "nff_reader.h"
#include "procedural.h"

namespace rt::test {

inline Scene spd(const std::string& name) { return readNff(std::string(RT_SCENE_DIR) + "/" + name + ".nff"); }

// The paper's scene, small: crowded into the first third of x, with spheres
// big enough to straddle region faces.
inline Scene procedural() {
    ProceduralParams p;
    p.spheres = 300;
    p.radius = 0.04;
    p.concentration = 1.0 / 3.0;
    p.seed = 42;
    return makeProceduralScene(p);
}

}  // namespace rt::test
