#include "frame_sequence.h"

#include <stdexcept>
#include <string>
#include <vector>

#include "balance/between_frames.h"
#include "frame_state_json.h"
#include "stops.h"
#include "subprocess.h"
#include "process/watchdog.h"

namespace rt {
namespace {

// jemalloc's (tb/rtsim.cpp links it; a sanitizer build has none).
extern "C" int mallctl(const char* name, void* old, size_t* oldLength, void* value, size_t length) __attribute__((weak));

// A frame's report is parsed, used and freed; the allocator would keep its
// pages for 30 s (malloc_conf in rtsim.cpp), and at several frames a second
// the parent would grow by a report's size every frame. Handed back at
// once instead.
void releaseFreedPages() {
    if (mallctl) mallctl("arena.4096.purge", nullptr, nullptr, nullptr, 0);  // (4096: every arena)
}

nlohmann::json frameEntry(int number, const nlohmann::json& report) {
    return {{"frame", number}, {"render_time_ns", report["render_time_ns"]}, {"slides", report["balance"].value("slides", 0)}};
}

// A sequence stopped in frame `k` (1-based) of `count`: the stopped frame's
// report so far, if it wrote one, with the frames before it.
nlohmann::json stoppedSequence(const std::optional<nlohmann::json>& partial, nlohmann::json frames, int k, int count,
                               const std::string& why) {
    const std::string which = "frame " + std::to_string(k) + " of " + std::to_string(count);
    nlohmann::json r = partial ? *partial : nlohmann::json::object();
    if (partial) {
        nlohmann::json entry = frameEntry(k, r);
        entry["incomplete"] = true;
        frames.push_back(entry);
    }
    r["frames"] = frames;
    r["incomplete"] = which + ": " + (partial ? r.value("incomplete", why) : why);
    return r;
}

}  // namespace

EarlierFrames runEarlierFrames(const std::vector<std::string>& args, RtsimOptions& o) {
    EarlierFrames out;
    const OrderlyStops orderly;  // a stop is passed to the frame running, and the sequence so far written
    const bool carry = o.machine.balance.dynamic(), resplit = o.machine.balance.betweenFrames();
    ResplitSequence sequence(o.machine);
    const MachineConfig first = o.machine;  // how frame 1 starts
    bool again = false;                     // resplit: every later frame is the first one again
    bool afresh = false;                    // resplit: the next frame starts where frame 1 did
    std::optional<nlohmann::json> last;     // the frame before's report
    for (int k = 0; k + 1 < o.frames; ++k) {
        if (stopSignal || wallPassed()) {  // (between two frames)
            out.exitCode = stopSignal ? 128 + int(stopSignal) : 3;
            out.stopped = stoppedSequence(std::nullopt, out.frames, k + 1, o.frames,
                                          stopSignal ? "stopped by signal " + std::to_string(int(stopSignal)) + " before it began"
                                                     : "the wall-clock limit was reached before it began");
            return out;
        }
        std::vector<std::string> extra = {"--as-frame", "--frame-index", std::to_string(k)};
        std::optional<TempFile> from, targets;  // (removed once the frame ran)
        if (carry && k > 0 && !again && !afresh) {
            from.emplace("rtsim-frame", ".json", last->dump() + "\n");
            extra.insert(extra.end(), {"--boundaries-from", from->path()});
        }
        if (resplit && k > 0 && !again) {
            targets.emplace("rtsim-frame", ".json", nlohmann::json(o.machine.targetBoundaries).dump() + "\n");
            extra.insert(extra.end(), {"--targets-from", targets->path()});
        }
        Child child(args, extra);
        if (child.stopped()) {
            const int code = child.exitCode();
            // Stopped (the child said why on stderr): its report so far, with
            // the frames before it. No image, no VCD (those are of the last frame).
            out.exitCode = code;
            out.childSaid = true;
            out.stopped = stoppedSequence(child.stoppedReport(), out.frames, k + 1, o.frames,
                                          code == 3 ? "stopped by the watchdog" : "stopped by a signal");
            return out;
        }
        last = child.report();
        if (!last) throw std::runtime_error("frame " + std::to_string(k + 1) + " of " + std::to_string(o.frames) + " failed");
        out.frames.push_back(frameEntry(k + 1, *last));
        releaseFreedPages();  // (the report before this one's)
        if (!carry && !resplit) continue;
        const FrameState state = frameStateFromReport(*last);
        if (carry) o.machine.startBoundaries = lastBoundaries(state, o.machine);
        if (!resplit) continue;
        const auto next = sequence.next(state, k + 1);
        out.frames.back()["then"] = sequence.said();
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
    report["frames"] = frames;
}

}  // namespace rt
