// A node's time ledger: where each picosecond of its local time went
// (busy, waiting for input, blocked on a full output buffer), and, at the
// frame's end, those figures as of that instant, so that busy + wait is the
// render time (invariant 6; doc/machine.md, "Accounting").
//
// A node running ahead of the kernel (a quantum) may be past the frame's
// end when the frame ends. Without a dynamic policy no step of a whole
// frame ends after it, and the ledger only trims; with one, it keeps a
// timeline of checkpoints (local time, busy time and end of the last step
// after each step and idle stretch) back to the last one the kernel has
// passed, and reads the figures at the end off it.
//
// Plain C++: the kernel's time comes in from the caller.
#pragma once
#include <string>
#include <vector>

#include "node/node_stats.h"

namespace rt {

class TimeLedger {
public:
    // `t`: the node's figures, kept in its NodeStats.
    explicit TimeLedger(NodeTimes& t) : t_(t) {}
    // Before the start: whether the node runs ahead of the kernel, and
    // whether it keeps a timeline (it runs ahead under a dynamic policy).
    void configure(bool decoupled, bool keepsTimeline) {
        decoupled_ = decoupled;
        keeps_ = keepsTimeline;
    }
    // The next frame (the figures are the node's: it clears them): nothing
    // charged, no timeline.
    void restart() {
        last_ = {};
        decoupled_ = keeps_ = false;
        timeline_.clear();
        timelineStart_ = 0;
    }

    // A step took the sum of `parts` (its cost by kind of work) and ended
    // at local time `now`.
    template <class Kernel>
    void charge(const BusyParts& parts, Picos now, Kernel kernel) {
        t_.busy += sumOf(parts);
        t_.busyBy += parts;
        last_ = parts;
        t_.lastActive = now;
        checkpoint(now, kernel);
    }
    // Waiting for input from `now`; until `now` (endWaiting).
    void startWaiting(Picos now) {
        t_.waiting = true;
        t_.waitingSince = now;
    }
    template <class Kernel>
    void endWaiting(Picos now, Kernel kernel) {
        t_.wait += now - t_.waitingSince;
        t_.waiting = false;
        checkpoint(now, kernel);
    }
    // Blocked on a full output (a direction, or kDirs + unit) from `now`;
    // until `now` (endBlocked: the time blocked, counted as wait).
    void startBlocked(Picos now, int on) {
        t_.blocking = true;
        t_.blockedSince = now;
        t_.blockedOn = on;
    }
    Picos endBlocked(Picos now) {
        const Picos blocked = now - t_.blockedSince;
        t_.blocking = false;
        t_.blocked += blocked;
        t_.wait += blocked;
        return blocked;
    }
    bool blocking() const { return t_.blocking; }

    // The node's figures at local time `now` (with a timeline): `kernel()`
    // is the kernel's time, before which no checkpoint but the last is
    // needed any more.
    template <class Kernel>
    void checkpoint(Picos now, Kernel kernel) {
        if (keeps_) record(now, kernel());
    }

    // The frame ended at `end`: busy and wait up to then (busy + wait =
    // end). A step still running then counts as busy only up to `end`; a
    // node still waiting then waited until then. `complete`: the frame
    // ended (not stopped by the watchdog or a signal). `who` names the node
    // in an error: a ledger that cannot account for the end is a bug.
    void endFrame(Picos end, bool complete, const std::string& who);

private:
    struct Checkpoint {
        Picos t, busy, lastActive;
        BusyParts busyBy;
    };
    void record(Picos now, Picos kernel);
    bool settleBlocked(Picos end);
    bool settleWaiting(Picos end);
    void endWithoutTimeline(Picos end, bool complete, const std::string& who);
    void endFromTimeline(Picos end, const std::string& who);

    NodeTimes& t_;
    BusyParts last_{};  // the last step's parts: what a cut at the frame's end takes first
    bool decoupled_ = false, keeps_ = false;
    std::vector<Checkpoint> timeline_;  // from timelineStart_ on (the older ones are dropped in bulk)
    size_t timelineStart_ = 0;
};

}  // namespace rt
