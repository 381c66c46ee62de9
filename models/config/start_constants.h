// --start-mix auto's measured constants (balance/initial_split.cpp says
// how they were measured), here so that the help of --start-mix and of
// --balance sample states them from one place: the tests a primary ray's
// generation is weighed against where the tests are the work; the longest
// column that starts by its objects (the half start or the object median;
// a longer one starts at the uniform split); the wire time of a hop, in
// handlings of it, from which the links set the frame and the half start
// gives way to the uniform split; by how many standard deviations of
// an even spread's box the half start must lighten a column's heaviest box
// to be taken; and the tests a primary ray is taken to do in a column's
// heaviest box beside its handling, against which the half start's
// longest box's rays are weighed on its link, with the margin they must
// exceed it by (balance/start_links.h).
#pragma once

namespace rt {

constexpr int kTestsPerGeneration = 8;
constexpr int kLongestColumnStartedByObjects = 8;
constexpr int kWirePerHandling = 10;
constexpr int kSpreadsLighter = 2;
// On the modern machine the unbalanced frame's busiest node took 386 ns a
// ray: 204 us over the 529 primary rays of its box (the built-in scene
// across the axis, f = 0.125, 5x5x5, 128x128), its 80 ns of handling and
// 31 tests. With the half start's busiest box 1.88 to 2 times the uniform
// split's, any count from 34 to 54 starts uniform at 400 MB/s (330 ns a
// ray on the wire), where the half start lost, and keeps the half start
// at 600 MB/s (220 ns), where it gained (doc/results/start_links.md).
constexpr int kTestsPerRayInHeaviestBox = 40;
// And by how much the half start's busiest link must exceed that floor of
// the uniform split's frame: the floor is rough, and where it was close
// the half start still gained (rings-2 at N = 7, 200 MB/s: its link 1.09
// times the floor, first frame 0.902 against 0.999), where the losses were
// at 1.29 times or more (doc/results/start_links.md).
constexpr double kLinkOverUniformFrame = 1.2;

}  // namespace rt
