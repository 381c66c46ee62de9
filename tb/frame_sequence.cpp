#include "frame_sequence.h"

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "between_frames.h"
#include "subprocess.h"

namespace rt {
namespace {

// Writes `j` to a fresh temporary file; its path.
std::string tempJson(const nlohmann::json& j) { return makeTempFile("rtsim-frame", j.dump() + "\n"); }

nlohmann::json frameEntry(int number, const nlohmann::json& report) {
    return {{"frame", number}, {"render_time_ns", report["render_time_ns"]}, {"slides", report["balance"].value("slides", 0)}};
}

// Frame k's child: its flags after the user's (frame 1, a frame that is the
// first one again and the starting split's trial start where the user said:
// --boundaries-from, or the policy's start).
struct FrameFlags {
    std::vector<std::string> extra;
    std::string from, targets;  // temporary files, removed once the frame ran
    ~FrameFlags() {
        if (!from.empty()) std::remove(from.c_str());
        if (!targets.empty()) std::remove(targets.c_str());
    }
};

}  // namespace

EarlierFrames runEarlierFrames(int argc, char** argv, RtsimOptions& o) {
    EarlierFrames out;
    const bool carry = o.machine.balance.dynamic(), resplit = o.machine.balance.policy == "resplit";
    ResplitSequence sequence(o.machine);
    const MachineConfig first = o.machine;  // how frame 1 starts
    bool again = false;                     // resplit: every later frame is the first one again
    bool afresh = false;                    // resplit: the next frame starts where frame 1 did
    for (int k = 0; k + 1 < o.frames; ++k) {
        FrameFlags f;
        f.extra = {"--as-frame", "--frame-index", std::to_string(k)};
        if (carry && k > 0 && !again && !afresh) {
            f.from = tempJson(out.frames.back().at("report"));
            f.extra.insert(f.extra.end(), {"--boundaries-from", f.from});
        }
        if (resplit && k > 0 && !again) {
            f.targets = tempJson(o.machine.targetBoundaries);
            f.extra.insert(f.extra.end(), {"--targets-from", f.targets});
        }
        Child child(argc, argv, f.extra);
        const std::optional<nlohmann::json> report = child.report(), stopped = child.stoppedReport();
        const std::string which = "frame " + std::to_string(k + 1) + " of " + std::to_string(o.frames);
        if (stopped) {
            // The watchdog stopped it (the child said why on stderr): its
            // report so far, with the frames before it. No image, no VCD
            // (those are of the last frame).
            nlohmann::json r = *stopped;
            nlohmann::json entry = frameEntry(k + 1, r);
            entry["incomplete"] = true;
            out.frames.push_back(entry);
            for (auto& e : out.frames) e.erase("report");
            r["frames"] = out.frames;
            r["incomplete"] = which + ": " + r.value("incomplete", std::string());
            out.stopped = r;
            return out;
        }
        if (!report) throw std::runtime_error(which + " failed");
        nlohmann::json entry = frameEntry(k + 1, *report);
        entry["report"] = *report;
        out.frames.push_back(entry);
        if (carry) o.machine.startBoundaries = lastBoundaries(*report, o.machine);
        if (!resplit) continue;
        const auto next = sequence.next(*report, k + 1);
        if (next) {
            o.machine.targetBoundaries = *next;
            afresh = sequence.startsAfresh();
            if (afresh) o.machine.startBoundaries = first.startBoundaries;
        } else {
            again = true;
            o.machine.startBoundaries = first.startBoundaries;
            o.machine.targetBoundaries = first.targetBoundaries;
        }
    }
    return out;
}

void listFrames(nlohmann::json& report, nlohmann::json frames, int count) {
    frames.push_back(frameEntry(count, report));
    for (auto& f : frames) f.erase("report");
    report["frames"] = frames;
}

}  // namespace rt
