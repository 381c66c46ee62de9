// The express rung (--fidelity express; doc/fidelity.md): a ray that would
// cross boxes whose nodes have no work of their own is sent past them: its
// sender's link carries it as in the exact model, then the express relay
// (one process for the machine, process/express_relay.h) moves it through
// those boxes, and the last one's link, the machine's own, delivers it to
// the first box on its way that has work (or the box it ends in, or the
// last before it leaves the world). The relay times each skipped box as the
// exact model would: its processor's step for a ray it passes on, then its
// link's slot, wire and latency; it takes the rays in the order they reach
// each box (it runs in simulated time, no further ahead than the soonest a
// ray still to be sent could reach a box), so each skipped processor and
// link serves them first come, first served. A skipped node's own steps
// and the relay's passes wait for each other, but in the order they are
// booked, which is not always the order of their times, and real messages
// on the skipped links do not share their slots with the express rays:
// that is the rung's error, measured in doc/fidelity.md; through nodes
// and links with no work of their own it is exact (tb/tests/test_timing.cpp).
//
// The path is the exact model's to the bit: each skipped box routes and
// "traces" the ray as its node would (route.h, Region::trace with no
// object: the ray ends there only if it reaches its light there), so the
// ray reaches the same box at the same parameter and the image is the
// same. A box holds no object for the whole frame only if no boundary
// moves: the rung runs with --balance none or median.
//
// The through rung (--fidelity through) goes further: past a box with
// objects too, where the ray crosses it without a hit (its node would trace
// it there and send it on) and its node is free: the sender's route skips
// it only where the node's processor is free by the time the ray would
// reach it, and the relay, as the ray reaches it, leaves the ray to a node
// that has work then (into its input: Link::deliverExpress). The relay
// books the node's step for the ray (the trace's cost) on its processor.
// What the node will do is not booked yet when a ray passes, so a pass can
// still go ahead of work that reaches the node then: that is this rung's
// error (doc/fidelity.md).
//
// This is the simulator's shortcut, not the machine's: the sender reads the
// boxes beyond its neighbour from here (architecture.md, invariant 4, holds
// for the machine it models: every ray still takes the links it would).
#pragma once
#include <array>
#include <stdexcept>
#include <vector>

#include "base/mesh_geometry.h"
#include "base/numbered_ring.h"
#include "channel/link.h"
#include "channel/route.h"

namespace rt {

// What the express path needs of each node: its box, whether rays may skip
// it, and what a ray adds passing through it; the relay's state of its
// processor and links. (What one hop touches is near the top: at
// 32x32x32 each node's entry is out of cache when a ray reaches it.)
struct ExpressLink {
    Picos wire = 0;       // a one-ray message's time on its wire
    Picos latency = 0;
    Picos free = 0;       // its wire is free of the express rays the relay sent on it so far
    uint64_t rays = 0;    // the rays the relay sent on it (the link's figures count them at the frame's end)
    Link* link = nullptr;
    uint32_t depth = 0;   // its slots
    // Its sender both works and is passed (--fidelity through): the relay's
    // rays take the wire in turn with the sender's own (Link::shareWire).
    bool shared = false;
    // Its slots, as the exact model's link (link.h): ray k goes on the wire
    // once ray k - depth was taken at the far end and the slot's credit is
    // back, one latency later. The take times of the last `depth` rays
    // (kUnknown: not yet taken), and the rays that wait for a slot.
    uint64_t wired = 0;
    NumberedRing<Picos> taken;  // by the ray's number on the link (grown as needed: most links carry few)
    std::vector<std::pair<uint32_t, Picos>> waiting;  // (the relay's slot, when it was ready), from waitingHead on
    size_t waitingHead = 0;
    static constexpr Picos kUnknown = ~Picos(0);
    // When ray number `wired` may go on the wire (kUnknown: not yet known).
    Picos slotFree() const {
        if (wired < depth) return 0;
        const Picos t = taken[wired - depth];
        return t == kUnknown ? kUnknown : t + latency;
    }
    // A ray's time from the start of its wire to the far end.
    Picos hop() const { return wire + latency; }
    // Ray number `wired` goes on the wire: its take time unknown yet.
    void putOnWire() {
        taken.fit(wired >= depth ? wired - depth : 0, wired);
        taken[wired++] = kUnknown;
    }
};
struct ExpressNode {
    Picos processorFree = 0;  // its processor is free of the express rays' passes so far (and of its own steps)
    Picos pass = 0;           // its processor's step for a ray it passes on (a receive and a send, at its speed)
    bool empty = false;       // holds no object and generates no primary ray: a ray passes it without work of its own
    bool through = false;     // (--fidelity through) holds objects, generates no primary ray: a ray it traces without a hit passes
    uint32_t queued = 0;      // (through) the rays its node held at its last step, its own and arrived or on their way
    // (through) Whether its node has work at `t`, as far as the bookings
    // tell: the sender's route and then the relay ask.
    bool busyAt(Picos t) const { return processorFree > t || queued > 0; }
    std::array<ExpressLink, kDirs> out;  // (no link: none)
    Box box;
};
// One box a ray skips: its node, the link it would leave by, its node's
// step for the ray, and where the ray enters its box (job.t0: should the
// node take the ray after all, --fidelity through).
struct ExpressHop {
    uint32_t node;
    int8_t dir;
    Picos step;
    double t0;
};

// --fidelity through: whether a ray in box `node` (one with objects, whose
// region owns job.t0) crosses it without a hit, traced as its node would
// to `tOut`: then the ray at its exit (job.t0) and the node's step for it;
// false if it hits or ends there (its node takes it). The machine's
// (machine_express.cpp), from its nodes' regions and costs.
class ThroughBoxes {
public:
    virtual ~ThroughBoxes() = default;
    virtual bool passes(size_t node, RayJob& job, double tOut, Picos& step) const = 0;
};

class ExpressRoutes {
public:
    ExpressRoutes(std::array<int, 3> dims, std::vector<ExpressNode> nodes);

    // Whether a ray that node `from` sends towards `dir` at job.t0, at its
    // time `now`, crosses at least one box it may skip: then the boxes it
    // skips (their nodes and the links they would send it on, the last one's into the
    // box that takes it) are appended to `hops`, from r.first on, and
    // job.t0 moves to where it enters that box. False (and job unchanged):
    // the neighbour takes it as in the exact model (it holds objects or
    // generates primary rays, or the ray ends or leaves the world there).
    // Under --fidelity through a box with objects is skipped only where its
    // node's processor is free by the time the ray would reach it, as far
    // as the passes and steps booked so far tell: a busy node takes the ray
    // into its queue, as in the exact model.
    struct Route {
        uint32_t first = 0, skipped = 0;
    };
    bool route(const Cell& from, int dir, RayJob& job, Picos now, Route& r, std::vector<ExpressHop>& hops) const;
    size_t indexOf(const Cell& c) const { return nodeIndex(c, dims_); }
    const ExpressNode& node(size_t i) const { return nodes_[i]; }
    ExpressNode& node(size_t i) { return nodes_[i]; }
    // The soonest a ray sent on any link reaches the next box (its wire and latency).
    Picos soonestHop() const { return soonestHop_; }
    // The frame's end: the rays the relay sent on each link, into the link's figures.
    void countOnLinks();
    // --fidelity through's boxes (none: only the empty ones are skipped).
    void passThrough(const ThroughBoxes* boxes) { through_ = boxes; }
    // A new frame: no express ray has used a processor or a wire yet.
    void restart() {
        for (ExpressNode& n : nodes_) {
            n.processorFree = 0;
            for (ExpressLink& l : n.out) {
                l.free = l.rays = l.wired = 0;
                l.taken = {};
                l.waiting.clear();
                l.waitingHead = 0;
            }
        }
    }

private:
    std::array<int, 3> dims_;
    std::vector<ExpressNode> nodes_;
    Picos soonestHop_ = 0;
    const ThroughBoxes* through_ = nullptr;
};

}  // namespace rt
