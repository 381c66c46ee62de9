// The JSON report of a run: configuration echo, render time, per node
// busy/wait/load and counts, per link messages and bytes by type, queue
// high-water marks, host and kernel statistics. Fields whose name contains
// "wall" are wall-clock measurements; everything else is deterministic.
#pragma once
#include <nlohmann/json.hpp>

#include "machine.h"

namespace rt {

nlohmann::json machineReport(const MachineResult& r, const MachineConfig& config);
// Its `config`: every machine setting, as the run used it, for an image of
// width x height.
nlohmann::json machineConfigJson(const MachineConfig& config, int width, int height);

}  // namespace rt
