// A --frames K sequence: the frames before the last, each rendered by a
// child rtsim (SystemC elaborates once per process), in turn; each starts
// where the one before left the boundaries (a dynamic policy's), and
// `resplit` chooses each next frame's boundaries between them
// (models/between_frames.h). This process then renders the last frame.
#pragma once
#include <optional>

#include <nlohmann/json.hpp>

#include "rtsim_cli.h"

namespace rt {

struct EarlierFrames {
    nlohmann::json frames = nlohmann::json::array();  // per frame: its number, render time, slides and report
    // The watchdog stopped a frame: the report so far, with the frames
    // before it and the stopped one listed (the caller writes it; exit 3).
    std::optional<nlohmann::json> stopped;
};

// Renders frames 1 .. K-1 of `o`'s sequence, and sets o.machine's start and
// target boundaries for frame K. Throws std::runtime_error if a frame fails.
EarlierFrames runEarlierFrames(int argc, char** argv, RtsimOptions& o);

// The last frame's report with the sequence's frames listed.
void listFrames(nlohmann::json& report, nlohmann::json frames, int count);

}  // namespace rt
