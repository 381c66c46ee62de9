// What a node counts and measures over a frame: the report's per-node
// figures (models/analysis/report.cpp, doc/report.md).
#pragma once
#include <cstdint>
#include <vector>

#include "balance/balance_agent.h"
#include "node/busy_parts.h"
#include "counters.h"
#include "base/units.h"

namespace rt {

// One boundary move, seen by the node that gave the slab.
struct SlideEvent {
    Picos t;
    int side;           // +1: the node's upper face along the axis, -1: its lower face
    double boundary;    // the face's new coordinate
    size_t objects;     // objects sent with the slab
};

// Where a node's time went (invariant 6: busy + wait = the render time),
// kept by its TimeLedger (time_ledger.h).
struct NodeTimes {
    Picos busy = 0, wait = 0;
    BusyParts busyBy{};            // busy by kind of work: sums to busy (busy_parts.h)
    Picos lastActive = 0;          // end of the last busy step
    bool waiting = false;          // waiting for work when the frame ended
    Picos waitingSince = 0;
    // Blocked on a full output buffer (--link-out-depth): part of `wait`.
    Picos blocked = 0;
    bool blocking = false;         // blocked when the frame ended
    Picos blockedSince = 0;
    int blockedOn = -1;            // the output it was blocked on (a direction, or kDirs + unit)
};

struct NodeStats : NodeTimes {
    Counters counters;             // operations, as sw counts them
    uint64_t raysTraced = 0;       // ray segments traced in this box
    uint64_t raysGenerated = 0;    // primary rays generated here
    uint64_t raysCreated = 0;      // generated + spawned here
    uint64_t raysTerminated = 0;   // ended here (hit, blocked, or left the world / reached its light)
    uint64_t raysForwarded = 0;    // sent to a neighbour
    // Of those, sent on without a segment traced here: the box did not own
    // where the ray was when it took it (a face moved since the ray was
    // sent or held, or a neighbouring column's face along the axis is
    // elsewhere). Each costs a send, and a receive if it came over a link,
    // for no tracing.
    uint64_t raysPassed = 0;
    // Of those, rays that came from a neighbouring column (a link across
    // the axis) to a box whose faces along the axis are not where that
    // column's are.
    uint64_t raysPassedBetweenColumns = 0;
    // --fidelity express (channel/express.h): rays sent past empty boxes in
    // one event, and the boxes they skipped (those boxes' nodes count none
    // of the skipped rays' steps or messages).
    uint64_t raysExpressed = 0, boxesSkipped = 0;
    uint64_t messagesSent = 0, messagesReceived = 0;
    uint64_t contributionsSent = 0;
    size_t queueHighWater = 0;     // local work + input messages arrived and not yet taken
    std::vector<SlideEvent> slides;        // slabs given
    uint64_t slidesTaken = 0, acks = 0;
    uint64_t objectsSent = 0, objectsReceived = 0;
    BalanceStats balance;                  // intervals, decisions and their loads' ages (dynamic policies)
};

}  // namespace rt
