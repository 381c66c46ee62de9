#include "frame_sequence.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "analysis/report.h"
#include "balance/between_frames.h"
#include "config_echo.h"
#include "machine/frame_state_of.h"
#include "machine/machine.h"
#include "stops.h"
#include "wall_limit.h"

namespace rt {
namespace {

// A frame of the list: its number, render time and slides, and when it
// began on the machine's clock (each frame starts where the one before ended).
nlohmann::json frameEntry(int number, double renderTimeNs, size_t slides, Picos start) {
    return {{"frame", number}, {"render_time_ns", renderTimeNs}, {"slides", slides}, {"starts_at_ns", double(start) / 1000.0}};
}

// A sequence stopped in frame `k` (1-based) of `count`: the stopped frame's
// report so far, if it ran, with the frames before it.
nlohmann::json stoppedSequence(const std::optional<nlohmann::json>& partial, nlohmann::json frames, int k, int count,
                               const std::string& why, Picos start = 0) {
    const std::string which = "frame " + std::to_string(k) + " of " + std::to_string(count);
    nlohmann::json r = partial ? *partial : nlohmann::json::object();
    if (partial) {
        nlohmann::json entry = frameEntry(k, r["render_time_ns"].get<double>(), r["balance"].value("slides", size_t(0)), start);
        entry["incomplete"] = true;
        frames.push_back(entry);
    }
    r["frames"] = frames;
    r["incomplete"] = which + ": " + why;
    return r;
}

// An earlier frame's machine: the sequence's, with the start and targets
// the loop chose, and nothing traced (the outputs are the last frame's).
MachineConfig earlierFrameConfig(const MachineConfig& m) {
    MachineConfig c = m;
    c.vcdPath.clear();
    c.vcdName.clear();
    c.traceNodes.clear();
    c.traceLinks.clear();
    c.showProgress = false;
    return c;
}

// The sequence's next frame by its machine, built now if it has none yet
// (on `scene`, whose view is then `view`; its elaboration timed); `another`:
// a frame follows.
MachineResult renderFrame(EarlierFrames& e, const Scene& scene, const View& view, const MachineConfig& m, bool another) {
    const bool building = !e.machine;
    if (building) e.machine = std::make_unique<MachineSession>(scene, m);
    else e.machine->next(view, m);
    MachineResult r = e.machine->run(another);
    if (building) e.elaborationSeconds = r.wallElaborationSeconds;
    return r;
}

// A frame stopped by the watchdog or a signal: its report so far, as the
// last frame's would be (its config echo that of frame `k`, 0-based).
nlohmann::json partialReport(const MachineResult& r, const MachineConfig& m, RtsimOptions& o, const Scene& scene, int k) {
    nlohmann::json report = frameReport(r, m, o).whole();
    const int last = o.frameIndex;
    o.frameIndex = k;
    report["config"] = configEcho(o, scene);
    o.frameIndex = last;
    return report;
}

}  // namespace

Report frameReport(const MachineResult& r, const MachineConfig& m, const RtsimOptions& o) {
    Report report = machineReportOf(r, m, o.fullReport() ? ReportDetail::Full : ReportDetail::Summary);
    report.json["report_detail"] = {{"level", o.fullReport() ? "full" : "summary"}, {"why", o.reportDetailWhy()}};
    return report;
}

Vec3 eyeOfFrame(const RtsimOptions& o, const Vec3& firstEye, int index) {
    if (o.eyeStep.empty()) return firstEye;
    return firstEye + Vec3(o.eyeStep[0], o.eyeStep[1], o.eyeStep[2]) * double(index);
}

void checkCameraPath(const RtsimOptions& o, const View& view, const Vec3& firstEye) {
    if (o.eyeStep.empty()) return;
    for (int k = 1; k < o.frames; ++k) {
        const Vec3 eye = eyeOfFrame(o, firstEye, k);
        const auto bad = [&](const std::string& why) {
            char at[96];
            std::snprintf(at, sizeof at, "(%g, %g, %g)", eye.x, eye.y, eye.z);
            throw std::invalid_argument("--eye-step: frame " + std::to_string(k + 1) + "'s eye " + at + " " + why);
        };
        if (!std::isfinite(eye.x) || !std::isfinite(eye.y) || !std::isfinite(eye.z)) bad("is not finite");
        const ViewFault f = viewFault(eye, view.at, view.up);
        if (f == ViewFault::EyeAtTarget) bad("is the point looked at");
        if (f != ViewFault::None) bad("looks along the view's up vector");  // (its up is the scene's, not zero)
    }
}

EarlierFrames runEarlierFrames(const Scene& scene, const Vec3& firstEye, RtsimOptions& o,
                               std::unique_ptr<MachineSession> machine) {
    EarlierFrames out;
    out.machine = std::move(machine);
    if (o.frames < 2) return out;
    const OrderlyStops orderly;  // a stop ends the frame running, and the sequence so far is written
    const bool carry = o.machine.balance.dynamic(), resplit = o.machine.balance.betweenFrames();
    ResplitSequence sequence(o.machine, &scene.objects);
    const MachineConfig first = o.machine;  // how frame 1 starts
    out.scene = std::make_unique<Scene>(scene);  // (the machine's, with frame 1's eye)
    out.scene->view.from = eyeOfFrame(o, firstEye, 0);
    View view = out.scene->view;
    for (int k = 0; k + 1 < o.frames; ++k) {
        if (stopSignal || wallPassed()) {  // (between two frames)
            out.exitCode = stopSignal ? 128 + int(stopSignal) : 3;
            out.why = stopSignal ? "stopped by signal " + std::to_string(int(stopSignal)) + " before it began"
                                 : "the wall-clock limit was reached before it began";
            out.stopped = stoppedSequence(std::nullopt, out.frames, k + 1, o.frames, out.why);
            return out;
        }
        view.from = eyeOfFrame(o, firstEye, k);
        const MachineConfig m = earlierFrameConfig(o.machine);
        const MachineResult r = renderFrame(out, *out.scene, view, m, true);
        if (k == 0) out.origin = r.frameStart;
        if (!r.incomplete.empty()) {  // the watchdog or a signal
            out.exitCode = stopSignal ? 128 + int(stopSignal) : 3;
            out.why = r.incomplete;
            Scene frameScene = *out.scene;
            frameScene.view = view;
            out.stopped = stoppedSequence(partialReport(r, m, o, frameScene, k), out.frames, k + 1, o.frames, r.incomplete,
                                          r.frameStart - out.origin);
            return out;
        }
        const FrameState state = frameStateOf(r, m);
        out.frames.push_back(frameEntry(k + 1, state.renderTimeNs, slideCount(r.boundaries), r.frameStart - out.origin));
        if (carry) o.machine.startBoundaries = lastBoundaries(state, o.machine);
        if (!resplit) continue;
        const auto next = sequence.next(state, k + 1);
        out.frames.back()["then"] = sequence.said();
        if (next) {
            o.machine.targetBoundaries = *next;
            // (A policy that starts at its objects tries the uniform split: it starts there.)
            if (sequence.startsAfresh())
                o.machine.startBoundaries = o.machine.balance.startsAtObjects() ? *next : first.startBoundaries;
        } else {  // (every later frame is the first one again)
            o.machine.startBoundaries = first.startBoundaries;
            o.machine.targetBoundaries = first.targetBoundaries;
        }
    }
    return out;
}

MachineResult runLastFrame(EarlierFrames& earlier, const Scene& scene, const MachineConfig& m, bool again) {
    MachineResult r = renderFrame(earlier, scene, scene.view, m, again);
    if (!again) earlier.machine.reset();  // (its memory back before the report is made)
    return r;
}

void listFrames(nlohmann::json& report, nlohmann::json frames, int count, Picos start) {
    frames.push_back(frameEntry(count, report["render_time_ns"].get<double>(), report["balance"].value("slides", size_t(0)), start));
    report["frames"] = frames;
}

}  // namespace rt
