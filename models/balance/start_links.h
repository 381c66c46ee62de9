// --start-mix auto's last word on the half start (doc/balancing.md, "Where
// sample starts"): the links its long boxes load.
//
// Half by the objects, half by the length makes the boxes where the
// objects are thin and the others long. Seen across the axis, a box's
// length is its share of the image: the long box generates that many
// primary rays, and they leave it, and every box behind it, on one
// lateral link each. Where the links are slow against the work a ray
// does in the heaviest box, that link sets the frame: on the modern
// machine at 400 MB/s (the built-in scene across the axis, f = 0.125,
// 5x5x5, 128x128) the half start's busiest box generated 1,058 primary
// rays against the uniform split's 529, its link ran 94 % busy and the
// first frame took 1.455 times the unbalanced one (the uniform start:
// 0.998); at 1 GB/s the half start gained (0.613 against 0.740).
#pragma once
#include "config/machine_config.h"
#include "config/start_constants.h"
#include "scene.h"

namespace rt {

// (kTestsPerRayInHeaviestBox: config/start_constants.h, with the help text)

// Where --start-mix auto chose the half start for `sample` (mix 0.5):
// the busiest box's primary rays at that start and at the uniform split
// (the camera's, at the image size cfg gives), E_half and E_uniform, a
// ray's wire time w and its work in the heaviest box, handling + 40
// tests. The half start's busiest link takes E_half w; the uniform
// split's frame at least E_uniform max(w, that work). Where the first is
// over kLinkOverUniformFrame (1.2) times the second, the start is the
// uniform split, and startMixWhy says why.
void weighStartLinks(MachineConfig& cfg, const Scene& scene);

}  // namespace rt
