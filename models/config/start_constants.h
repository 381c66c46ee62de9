// Two of --start-mix auto's measured constants (balance/initial_split.h
// says how they were measured), here so that the help of --start-mix and of
// --balance sample states them from one place: the tests a primary ray's
// generation is weighed against where the tests are the work, and the
// longest column that starts by its objects (the half start or the object
// median; a longer one starts at the uniform split).
#pragma once

namespace rt {

constexpr int kTestsPerGeneration = 8;
constexpr int kLongestColumnStartedByObjects = 8;

}  // namespace rt
