// rtsim's summary on stdout (without -q): the render time and the speed-up
// over one node, each node's busy, wait and load, the traffic, the busiest
// links, the balancing against its bounds, the frames of a sequence.
#pragma once
#include <nlohmann/json.hpp>

#include "machine/machine.h"
#include "rtsim_cli.h"
#include "wall_clock.h"

namespace rt {

// `report`: the run's report; `baselineNs`: the 1x1x1 run's render time (<= 0: none);
// `wall`: the run's wall-clock time by part.
void printSummary(const Scene& scene, const RtsimOptions& o, const MachineResult& r, const nlohmann::json& report,
                  double baselineNs, const WallClock& wall);

}  // namespace rt
