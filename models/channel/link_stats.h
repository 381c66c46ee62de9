// What a link measures (the report's per-link figures: models/analysis/report.cpp,
// doc/report.md): messages, bytes and wire time by type, waits, latency
// distributions and high-water marks.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>

#include "base/busy_windows.h"
#include "base/histogram.h"
#include "channel/message.h"
#include "base/units.h"

namespace rt {

// A link's figures but those by message type (what it keeps as a struct).
struct LinkFlow {
    // Of the messages consumed: time from being sent to having a slot (in
    // the sender's backlog, its output buffer), from having a slot to
    // starting on the wire (behind other messages), and from being sent to
    // being consumed (its latency as the receiver sees it), for rays,
    // contributions and credit, and for balancing messages (isControl).
    Picos slotWait = 0, wireWait = 0;
    uint64_t consumed = 0;
    // High-water marks in simulated time (so the same in every exact mode,
    // whatever order the kernel runs the processes in):
    size_t backlogHighWater = 0;  // messages sent and not yet on the wire, at once
    size_t bufferHighWater = 0;   // messages on the wire or arrived and not consumed, at once
    // Saturation in time: the wire's busy time over windows of the frame
    // (--link-stats full), and the time it was busy while a message that
    // had its slot waited for it (the union of the messages' wire waits:
    // the link held rays back then).
    BusyWindows windows;
    Picos saturated = 0;
    // The latencies (the first comment's third figure), last. A link adds
    // its messages to these figures a batch at a time (Link::foldTaken),
    // not at each take: on a large mesh they are out of cache at each.
    Histogram latency, controlLatency;
};

struct LinkStats : LinkFlow {
    std::array<uint64_t, kMsgTypes> messages{}, bytes{};
    std::array<Picos, kMsgTypes> wire{};  // time on the wire, by type (the wire's busy time: their sum)
    Picos wireBusy() const {
        Picos b = 0;
        for (Picos w : wire) b += w;
        return b;
    }
};

}  // namespace rt
