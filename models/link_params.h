// A link's settings (--link-* and --fb-* flags) and the times they give a
// message: its time on the wire, how long it holds the link, the soonest it
// can arrive. The link itself, which schedules messages with them: link.h.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "units.h"

namespace rt {

struct LinkParams {
    Picos latency = 100000;   // 100 ns
    double bandwidth = 1e9;   // bytes per second
    int depth = 16;           // messages the link holds before back-pressure
    // The control lane (link.h): slots of a second virtual channel for load
    // reports, slides and acks, which go on the wire ahead of waiting rays.
    // 0 (the default): no lane; control messages queue with the rays, in one
    // FIFO. With a lane, decisions use loads a fraction of an interval old
    // instead of loads queued behind rays, but rounds come every interval
    // instead of every few, and `slide`'s first frame loses more often
    // (doc/balancing.md, "The control lane"). The frame-buffer ports carry
    // no control messages.
    int controlDepth = 0;
    // The sender's output buffer (link.h): messages sent and still waiting
    // for a flow-control slot, per lane. A node whose buffer is full blocks
    // until the receiver frees a slot. 0 (the default): unbounded, a sender
    // never blocks.
    int outDepth = 0;
};

// A message of `bytes` on a wire of `bandwidth` bytes per second: its time
// on the wire in picoseconds, unrounded (the balancing guard's estimates).
inline double wirePicos(uint32_t bytes, double bandwidth) { return double(bytes) * 1e12 / bandwidth; }

// The same rounded up to whole picoseconds, at least 1 ps: what a link
// charges.
inline Picos wireTime(uint32_t bytes, double bandwidth) {
    return std::max<Picos>(1, Picos(std::ceil(wirePicos(bytes, bandwidth))));
}

// How long a message `wire` ps long keeps a link of `p` busy, by the
// narrower of its two limits: the wire, or its share of the slots' round
// trip (a message holds a slot from its start on the wire until the
// receiver's credit is back: its transfer and the latency there and back,
// so `depth` slots carry one every (wire + 2 latency) / depth).
// LinkSendIf::occupied is this summed over the messages sent.
inline double occupancy(const LinkParams& p, double wire) {
    return std::max(wire, (wire + 2 * double(p.latency)) / p.depth);
}

// The soonest after its sender's time that a message on a link of `p`
// arrives: the latency and the smallest message's time on the wire.
inline Picos linkLookahead(const LinkParams& p, uint32_t smallest) { return p.latency + wireTime(smallest, p.bandwidth); }

}  // namespace rt
