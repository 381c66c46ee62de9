// Bad input: the message is one line naming where and what ("file:12: ...").
#pragma once
#include <stdexcept>
#include <string>

namespace rt {

struct SceneError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The largest magnitude of a scene's number (a coordinate, a radius, a
// camera's or a light's position), in a file or a flag: far beyond any
// scene, and far enough from overflow that boxes, grids and the camera's
// frame built from it stay exact (a sphere of radius 1e98 collapsed the
// world box's planes, scripts/fuzz.sh; an eye at 1e200 squared its
// distance to inf and traced every ray as NaN).
constexpr double kMaxSceneMagnitude = 1e9;

}  // namespace rt
