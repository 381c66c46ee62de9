// The reference runs beside a run, in two child processes at once: the
// same frame on a 1x1x1 mesh with the same costs (the speed-up), and the
// same frame balanced the other way (the default policy if the run does not
// balance, no balancing if it does: the paper's Fig. 4 ratio, beside its
// bound). --no-baseline skips both.
#pragma once
#include <nlohmann/json.hpp>

#include "rtsim_cli.h"

namespace rt {

// Adds `baseline` and `comparison` to `report` (the run's); returns the
// 1x1x1 run's render time in ns (<= 0: none). A reference run that fails is
// a warning, not an error.
double addReferenceRuns(nlohmann::json& report, int argc, char** argv, const RtsimOptions& o);

}  // namespace rt
