// --trace-nodes busiest[:K] (doc/machine.md, "Finding a bottleneck"):
// which nodes and links are worth tracing, chosen from a first pass. The
// run is made twice: once without waveforms, in a child process (the whole
// sequence of frames, so that its last frame is the one traced), and once
// tracing what that pass's report shows held the frame back: the K nodes
// with the most busy time, and the K links that were busy longest with
// messages waiting for them (the report's ranking of busiest_links,
// extended to K: saturated_ns, then utilisation).
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/mesh_geometry.h"
#include "rtsim_cli.h"

namespace rt {

struct TraceChoice {
    std::vector<Cell> nodes;
    std::vector<std::pair<Cell, int>> links;  // (sending node, direction; kDirs: its frame-buffer port)
};

// The choice from a report (ties: the first in the report's order).
TraceChoice busiestOf(const nlohmann::json& report, int k);

// Runs the first pass with `command` (argv[0] first) and sets
// o.machine.traceNodes and traceLinks to its choice, which it returns;
// nothing (tracing everything, as without the flag) if the pass did not
// end normally.
std::optional<TraceChoice> traceBusiest(const std::vector<std::string>& command, RtsimOptions& o);

// The report's trace_busiest: K and what was chosen.
nlohmann::json traceChoiceJson(int k, const TraceChoice& c);

}  // namespace rt
