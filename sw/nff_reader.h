// Reader for Eric Haines' Neutral File Format (NFF), every entity used by
// the SPD scenes: v/from/at/up/angle/hither/resolution, b, l, f, s, p, pp, c
// and # comments. Throws SceneError with "file:line: what was expected".
#pragma once
#include <string>

#include "scene.h"
#include "scene_error.h"

namespace rt {

Scene readNff(const std::string& path);
// Same, from text; `name` stands for the file in error messages.
Scene parseNff(const std::string& text, const std::string& name);

}  // namespace rt
