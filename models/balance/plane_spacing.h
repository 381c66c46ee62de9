// How far apart a policy puts planes that must be at least the minimum
// thickness apart. Planes a policy computes may become a later frame's
// targets, and the machine checks a target's boxes against the minimum
// thickness exactly (withInnerPlanes, initial_split.h): b + m - b can round
// below m, and a box one rounding thinner stopped a run (`sample --frames
// 3` on 32x32x32, where the start put boxes at the minimum). A hair more
// keeps every box at least m thick after the rounding.
#pragma once

namespace rt {

constexpr double planeSpacing(double minThickness) { return minThickness * (1 + 1e-9); }

}  // namespace rt
