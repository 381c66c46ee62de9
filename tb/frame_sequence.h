// A --frames K sequence: the frames before the last, each rendered by a
// child rtsim (SystemC elaborates once per process), in turn; each starts
// where the one before left the boundaries (a dynamic policy's), and
// `resplit` chooses each next frame's boundaries between them
// (models/balance/between_frames.h). This process then renders the last frame.
// Only the last frame's report is kept between frames (one entry per
// frame: its time and slides), so memory does not grow with K.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rtsim_cli.h"

namespace rt {

struct EarlierFrames {
    nlohmann::json frames = nlohmann::json::array();  // per frame: its number, render time and slides
    // A frame stopped (the watchdog, a signal, the wall-clock limit): the
    // report so far, with the frames before it and the stopped one listed,
    // and the exit code (3, 128 + N); the caller writes it.
    std::optional<nlohmann::json> stopped;
    int exitCode = 0;
    bool childSaid = false;  // the stopped frame's own run said why (on stderr)
};

// Renders frames 1 .. K-1 of `o`'s sequence, and sets o.machine's start and
// target boundaries for frame K. Throws std::runtime_error if a frame fails.
EarlierFrames runEarlierFrames(const std::vector<std::string>& args, RtsimOptions& o);

// The last frame's report with the sequence's frames listed.
void listFrames(nlohmann::json& report, nlohmann::json frames, int count);

}  // namespace rt
