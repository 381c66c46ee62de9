// A --frames K sequence: the frames before the last, rendered in turn by
// one machine in one elaboration (MachineSession: between two frames the
// host phase re-boxes the nodes, in simulated time); each starts
// where the one before left the boundaries (a dynamic policy's), and
// `resplit` chooses each next frame's boundaries between them from what the
// frame before left behind (balance/frame_state.h, in memory: no report
// between frames). The caller then renders the last frame. Only one entry
// per frame (its time and slides) is kept, so memory does not grow with K.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "analysis/report.h"
#include "machine/machine.h"
#include "rtsim_cli.h"
#include "scene.h"

namespace rt {

struct EarlierFrames {
    // The machine that rendered them, to render the last one (null: one frame).
    std::unique_ptr<Scene> scene;  // (the machine's: it holds a reference)
    std::unique_ptr<MachineSession> machine;
    double elaborationSeconds = 0;  // building it (once), until its first simulated event
    // Where frame 1 began on the machine's clock: after --max-error's
    // calibration frames, if they ran in it; the frames' starts count from it.
    Picos origin = 0;
    nlohmann::json frames = nlohmann::json::array();  // per frame: its number, render time and slides
    // A frame stopped (the watchdog, a signal, the wall-clock limit): the
    // report so far, with the frames before it and the stopped one listed,
    // the exit code (3, 128 + N) and why; the caller writes and says it.
    std::optional<nlohmann::json> stopped;
    int exitCode = 0;
    std::string why;
};

// Renders frames 1 .. K-1 of `o`'s sequence of `scene` (its eye at frame
// 1's place, `firstEye`; --eye-step moves it each frame), and sets
// o.machine's start and target boundaries for frame K. Throws
// std::runtime_error if a frame fails. `machine`: one already built (on
// `scene`) that renders them, and the last (--max-error's calibration,
// fidelity_choice.h); null: the first frame builds one.
EarlierFrames runEarlierFrames(const Scene& scene, const Vec3& firstEye, RtsimOptions& o,
                               std::unique_ptr<MachineSession> machine = nullptr);

// The last frame (`scene`'s view), by the machine of the frames before it
// (or a new one); `again`: the machine is kept in `earlier` to render it
// once more (a first pass: trace_busiest.h).
MachineResult runLastFrame(EarlierFrames& earlier, const Scene& scene, const MachineConfig& m, bool again = false);

// A frame's report, at the detail --report-detail gives (models/analysis/report.h).
Report frameReport(const MachineResult& r, const MachineConfig& m, const RtsimOptions& o);

// The eye of frame `index` (0-based) of a camera path from `firstEye`.
Vec3 eyeOfFrame(const RtsimOptions& o, const Vec3& firstEye, int index);
// Every frame's camera of the path, checked before any runs: an eye that
// is not finite, is the point looked at, or looks along `up` would render
// a flat background (or nothing) with exit 0. Throws std::invalid_argument
// naming --eye-step and the frame.
void checkCameraPath(const RtsimOptions& o, const View& view, const Vec3& firstEye);

// The last frame's report with the sequence's frames listed.
void listFrames(nlohmann::json& report, nlohmann::json frames, int count, Picos start);

}  // namespace rt
