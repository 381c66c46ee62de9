// Judging a run's boundary movement after the transient: converged,
// oscillating or diverging (doc/balancing.md, "Stability"). Used by the report,
// the stability map script (through the report) and the tests.
#pragma once
#include <string>
#include <vector>

#include "machine/machine.h"

namespace rt {

enum class Stability { Converged = 0, Oscillating = 1, Diverging = 2 };
const char* stabilityName(Stability s);

struct StabilityVerdict {
    Stability overall = Stability::Converged;  // the worst boundary's
    int converged = 0, oscillating = 0, diverging = 0;
};

// Looks at the moves of each boundary in the second half of the frame
// (the transient is the first half): a boundary oscillates if its moves
// change direction at least 3 times with a mean step above 5 % of the
// initial thickness, and diverges if, besides, its steps in the last quarter
// are 1.5 times those of the third quarter or more. Otherwise (few moves,
// small ones, or a drift one way) it has converged.
StabilityVerdict judgeStability(const std::vector<BoundaryHistory>& boundaries, Picos renderTime,
                                double initialThickness);

}  // namespace rt
