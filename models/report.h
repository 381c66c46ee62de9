// The JSON report of a run: configuration echo, render time, per node
// busy/wait/load and counts, per link messages and bytes by type, queue
// high-water marks, host and kernel statistics. Fields whose name contains
// "wall" are wall-clock measurements; everything else is deterministic.
#pragma once
#include <vector>
#include <nlohmann/json.hpp>

#include "machine.h"

namespace rt {

nlohmann::json machineReport(const MachineResult& r, const MachineConfig& config);
// Its `config`: every machine setting, as the run used it, for an image of
// width x height.
nlohmann::json machineConfigJson(const MachineConfig& config, int width, int height);

// A report's `links` (their indices) ranked by what held the frame back:
// the time the wire was busy with messages waiting for it (saturated_ns),
// then the utilisation; ties keep the report's order. `busiest_links` and
// --trace-nodes busiest take their first.
std::vector<size_t> linksByBacklog(const nlohmann::json& links);

}  // namespace rt
