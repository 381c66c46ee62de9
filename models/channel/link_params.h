// A link's settings (--link-* and --fb-* flags) and the times they give a
// message: its time on the wire, how long it holds the link, the soonest it
// can arrive. The link itself, which schedules messages with them: link.h.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <tuple>

#include <vector>

#include "base/param.h"
#include "base/units.h"

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
    // The sending end's link engine: its time to take one message, before
    // the message's bytes go out; the wire is held meanwhile. 0 unless the
    // links handle the hops (MachineConfig::hopsByLinks, --hop-handling link),
    // when it is the sender's --cost-send.
    Picos engine = 0;
};

// The settings a flag sets: --link-NAME for the mesh links (and --link-set's
// keys, NAME with '_' for '-'), --fb-NAME for the frame-buffer ports where
// they have it; echoed in the report's config.link, link_overrides and
// fb_port (base/param.h).
// (The bandwidth by its bits: a NaN, which checks refuse, is not equal to every value.)
inline bool operator<(const LinkParams& a, const LinkParams& b) {
    const auto key = [](const LinkParams& p) {
        uint64_t bits;
        std::memcpy(&bits, &p.bandwidth, sizeof bits);
        return std::make_tuple(p.latency, bits, p.depth, p.controlDepth, p.outDepth, p.engine);
    };
    return key(a) < key(b);
}

// One copy of each set of parameters, for the process's lifetime: links
// with the same (most of a mesh's) share it (link.cpp).
const LinkParams& sharedParams(const LinkParams& p);

inline const std::vector<Param<LinkParams>>& linkParams() {
    static const std::vector<Param<LinkParams>> rows = {
        alsoForPorts(timeParam("latency", &LinkParams::latency, "/latency_ns", "link latency"), "frame-buffer port latency"),
        alsoForPorts(rateParam("bandwidth", &LinkParams::bandwidth, "/bandwidth_bytes_per_s", "link bandwidth"),
                     "frame-buffer port bandwidth"),
        alsoForPorts(numberParam("depth", &LinkParams::depth, 1, 1000000, "/depth", "messages a link holds before back-pressure"),
                     "messages a frame-buffer port holds"),
        numberParam("control-depth", &LinkParams::controlDepth, 0, 1000000, "/control_depth",
                    "slots of the links' control lane (load reports, slides, acks ahead of rays); 0: no lane, one FIFO"),
        alsoForPorts(numberParam("out-depth", &LinkParams::outDepth, 0, 1000000, "/out_depth",
                                 "messages a sender's output buffer holds per link and lane while they wait for a slot; a "
                                 "node whose buffer is full blocks (charged as wait, reported as blocked); 0: unbounded, "
                                 "senders never block"),
                     "messages a node's output buffer holds per frame-buffer port; a node whose buffer is full blocks; 0: "
                     "unbounded"),
    };
    return rows;
}

// A message of `bytes` on a link of `p`: its time on the wire in
// picoseconds (the engine's handling, then the bytes at the bandwidth),
// unrounded (the balancing guard's estimates).
inline double bytesPicos(uint32_t bytes, double bandwidth) { return double(bytes) * 1e12 / bandwidth; }
inline double wirePicos(const LinkParams& p, uint32_t bytes) { return double(p.engine) + bytesPicos(bytes, p.bandwidth); }

// The same with the bytes' time rounded up to whole picoseconds, at least
// 1 ps: what a link charges.
inline Picos wireTime(const LinkParams& p, uint32_t bytes) {
    return p.engine + std::max<Picos>(1, Picos(std::ceil(bytesPicos(bytes, p.bandwidth))));
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
inline Picos linkLookahead(const LinkParams& p, uint32_t smallest) { return p.latency + wireTime(p, smallest); }

}  // namespace rt
