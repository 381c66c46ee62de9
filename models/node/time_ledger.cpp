#include "node/time_ledger.h"

#include <algorithm>
#include <stdexcept>

namespace rt {

void TimeLedger::record(Picos now, Picos kernel) {
    while (timelineStart_ + 1 < timeline_.size() && timeline_[timelineStart_ + 1].t <= kernel) ++timelineStart_;
    if (timelineStart_ > 64 && timelineStart_ * 2 > timeline_.size()) {
        timeline_.erase(timeline_.begin(), timeline_.begin() + std::ptrdiff_t(timelineStart_));
        timelineStart_ = 0;
    }
    timeline_.push_back({now, t_.busy, t_.lastActive, t_.busyBy});
}

void TimeLedger::endFrame(Picos end, bool complete, const std::string& who) {
    if (settleBlocked(end) || settleWaiting(end)) return;
    if (!decoupled_) {  // lockstep: at most the last step runs past the end
        if (t_.lastActive > end) {
            trim(t_.busyBy, last_, t_.lastActive - end);
            t_.busy -= t_.lastActive - end;
            t_.lastActive = end;
        }
        return;
    }
    const Picos local = t_.busy + t_.wait;  // the node's local time: every picosecond is one or the other
    if (local <= end) {  // idle from its local time until the end (asleep while the kernel caught up)
        t_.wait += end - local;
        return;
    }
    if (keeps_) endFromTimeline(end, who);
    else endWithoutTimeline(end, complete, who);
}

// Blocked on a full output since before the end: blocked until then.
bool TimeLedger::settleBlocked(Picos end) {
    if (!t_.blocking || t_.blockedSince > end) return false;
    endBlocked(end);
    return true;
}

// Waiting for input since before the end: waited until then. (Waiting from
// past the end, for the kernel to catch up with it, it was ahead of the end.)
bool TimeLedger::settleWaiting(Picos end) {
    if (!t_.waiting) return false;
    t_.waiting = false;
    if (t_.waitingSince > end) return false;
    t_.wait += end - t_.waitingSince;
    return true;
}

// Without a dynamic policy every step moves credit (a ray's, or the frame
// buffer's share), which reaches unit 0 after the step ends (in any mode: a
// message never arrives before it is sent): no step of a whole frame ends
// after it, and a node past its end got there idling.
void TimeLedger::endWithoutTimeline(Picos end, bool complete, const std::string& who) {
    if (t_.lastActive > end) {
        if (complete) throw std::logic_error(who + ": a step ended after the frame, with no dynamic policy");
        // A run stopped midway (watchdog, signal) at the kernel's time, which
        // a node with work may have run past: its figures there are not
        // kept, so it counts as busy from the stop to the end of its last
        // step (an incomplete report's figures are the run's so far; busy +
        // wait is still the time).
        const Picos cut = std::min(t_.busy, t_.lastActive - end);
        trim(t_.busyBy, last_, cut);
        t_.busy -= cut;
        t_.lastActive = end;
    }
    t_.wait = end - t_.busy;
}

// Ahead of the end: between two checkpoints the node waited, then ran one
// step (or only idled), so the busy time at `end` is the earlier one's plus
// whatever of that step lies before `end`. (The kernel stopped at or before
// `end`, so the timeline reaches back to it.)
void TimeLedger::endFromTimeline(Picos end, const std::string& who) {
    Checkpoint prev{0, 0, 0, BusyParts{}};
    for (size_t i = timelineStart_; i < timeline_.size(); ++i) {
        const Checkpoint& c = timeline_[i];
        if (c.t > end) {
            const Picos stepStart = c.t - (c.busy - prev.busy);
            const bool running = end > stepStart;  // a step was running at the end
            t_.busy = prev.busy + (running ? end - stepStart : 0);
            BusyParts step = c.busyBy;  // the step's parts, and of them the share before the end
            step -= prev.busyBy;
            t_.busyBy = prev.busyBy;
            t_.busyBy += scaledTo(step, t_.busy - prev.busy);
            t_.wait = end - t_.busy;
            t_.lastActive = running ? end : prev.lastActive;
            return;
        }
        prev = c;
    }
    throw std::logic_error(who + ": local time past the end of the frame, but no checkpoint after it");
}

}  // namespace rt
