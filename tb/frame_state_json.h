// A report read back into what its frame left behind (balance/frame_state.h):
// the user's edge of the frame state (--boundaries-from). The report holds
// the state to the bit (models/analysis/report.cpp writes it), so a frame
// continued from its report is the frame continued in memory.
#pragma once
#include <nlohmann/json.hpp>

#include "balance/frame_state.h"

namespace rt {

// Throws std::runtime_error ("not an rtsim report (...)") where a field the
// state needs is missing or of the wrong type: `config.mesh`,
// `config.balance.axis` and `boundaries` at least (a file of those alone is
// where the boundaries start, as scripts/experiments/partition_search.py
// writes it: no nodes, no render time). A node without work_by_position
// traced nothing; a report older than `totals.ray_wire_ns` gives the links'
// own wire times summed.
FrameState frameStateFromReport(const nlohmann::json& r);

}  // namespace rt
