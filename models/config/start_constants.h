// --start-mix auto's measured constants (balance/initial_split.cpp says
// how they were measured), here so that the help of --start-mix and of
// --balance sample states them from one place: the tests a primary ray's
// generation is weighed against where the tests are the work; the longest
// column that starts by its objects (the half start or the object median;
// a longer one starts at the uniform split); the wire time of a hop, in
// handlings of it, from which the links set the frame and the half start
// gives way to the uniform split; and by how many standard deviations of
// an even spread's box the half start must lighten a column's heaviest box
// to be taken.
#pragma once

namespace rt {

constexpr int kTestsPerGeneration = 8;
constexpr int kLongestColumnStartedByObjects = 8;
constexpr int kWirePerHandling = 10;
constexpr int kSpreadsLighter = 2;

}  // namespace rt
