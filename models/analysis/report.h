// The JSON report of a run: configuration echo, render time, per node
// busy/wait/load and counts, per link messages and bytes by type, queue
// high-water marks, host and kernel statistics. Fields whose name contains
// "wall" are wall-clock measurements; everything else is deterministic.
#pragma once
#include <vector>
#include <nlohmann/json.hpp>

#include "machine/machine.h"

namespace rt {

// How much of each node and link the report keeps (--report-detail; doc/report.md,
// "Report detail"). Summary keeps what the summary, the mesh map, the frame
// loop (a node's grid and work by position: `resplit`'s forecast) and
// scripts read, and leaves out what grows with the mesh but few read: a
// node's balancing intervals, a link's settings, counts by message type,
// latency percentiles and high-water marks. A 32x32x32 mesh's report was
// 334 MB.
enum class ReportDetail { Full, Summary };

nlohmann::json machineReport(const MachineResult& r, const MachineConfig& config,
                             ReportDetail detail = ReportDetail::Full);
// Its `config`: every machine setting, as the run used it, for an image of
// width x height.
nlohmann::json machineConfigJson(const MachineConfig& config, int width, int height);

// A report's `links` (their indices) ranked by what held the frame back:
// the time the wire was busy with messages waiting for it (saturated_ns),
// then the utilisation; ties keep the report's order. `busiest_links` and
// --trace-nodes busiest take their first.
std::vector<size_t> linksByBacklog(const nlohmann::json& links);

}  // namespace rt
