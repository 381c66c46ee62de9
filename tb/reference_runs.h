// The reference runs beside a run, in two child processes at once: the
// same frame on a 1x1x1 mesh with the same costs (the speed-up), and the
// same frame balanced the other way (the recommended policy if the run does not
// balance, no balancing if it does: the paper's Fig. 4 ratio, beside its
// bound). --no-baseline skips both.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rtsim_cli.h"

namespace rt {

struct ReferenceRuns {
    double baselineNs = -1;  // the 1x1x1 run's render time in ns (<= 0: none)
    // A stop while they ran (the wall-clock limit: 3; a signal: 128 + N):
    // the report says which was stopped (reference_runs_stopped); 0: none.
    int stopCode = 0;
    bool ran = false;  // either ran (not with --no-baseline, nor on a 1x1x1 mesh with one node along the axis)
};

// Adds `baseline` and `comparison` to `report` (the run's). A reference run
// that fails is a warning, not an error.
ReferenceRuns addReferenceRuns(nlohmann::json& report, const std::vector<std::string>& args, const RtsimOptions& o);

}  // namespace rt
