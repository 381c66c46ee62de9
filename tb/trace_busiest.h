// --trace-nodes busiest[:K] (doc/machine.md, "Finding a bottleneck"):
// which nodes and links are worth tracing, chosen from a first pass. The
// last frame is rendered twice by the sequence's machine (frame_sequence.h),
// from the same start: once without waveforms, and once tracing what that
// pass's report shows held the frame back: the K nodes
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
#include "frame_sequence.h"
#include "rtsim_cli.h"

namespace rt {

struct TraceChoice {
    std::vector<Cell> nodes;
    std::vector<std::pair<Cell, int>> links;  // (sending node, direction; kDirs: its frame-buffer port)
};

// The choice from a report (ties: the first in the report's order).
TraceChoice busiestOf(const nlohmann::json& report, int k);

// Runs the first pass (the last frame of `earlier`'s sequence, `scene`'s
// view, untraced) and sets o.machine.traceNodes and traceLinks to its
// choice, which it returns; nothing (tracing everything, as without the
// flag) if the pass did not end normally.
std::optional<TraceChoice> traceBusiest(EarlierFrames& earlier, const Scene& scene, RtsimOptions& o);

// The report's trace_busiest: K and what was chosen.
nlohmann::json traceChoiceJson(int k, const TraceChoice& c);

}  // namespace rt
