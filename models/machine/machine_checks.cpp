// The conservation laws (architecture.md, invariants 2, 3 and 6), checked
// at the end of every run that completed: a broken one is an error, not a
// warning (doc/machine.md, "Accounting").
#include <sstream>
#include <stdexcept>

#include "machine/machine.h"

namespace rt {

void Machine::checkConservation() const {
    if (stopped()) return;  // an incomplete run: nothing to conserve yet
    uint64_t created = primaryMisses_, terminated = primaryMisses_, sent = primaryMisses_;
    for (const Node& n : nodes_) {
        created += n.stats().raysCreated;
        terminated += n.stats().raysTerminated;
        sent += n.stats().contributionsSent;
    }
    if (!controller().done()) throw std::runtime_error("conservation: the frame never completed");
    if (created != terminated) {
        std::ostringstream s;
        s << "conservation: " << created << " rays created but " << terminated << " terminated";
        throw std::runtime_error(s.str());
    }
    uint64_t received = primaryMisses_;
    for (const FrameBufferUnit& u : units_) received += u.stats().contributions;
    if (sent != received) {
        std::ostringstream s;
        s << "conservation: " << sent << " contributions sent but " << received << " received";
        throw std::runtime_error(s.str());
    }
    // Time accounting: every node was busy or waiting until the frame was done.
    const Picos end = controller().renderTime();
    for (const Node& n : nodes_) {
        const NodeStats& s = n.stats();
        if (s.lastActive > end || s.busy + s.wait != end)
            throw std::runtime_error(std::string("time accounting: busy + wait != render time at ") + n.name() +
                                     " (busy " + std::to_string(s.busy) + ", wait " + std::to_string(s.wait) +
                                     ", last active " + std::to_string(s.lastActive) + ", end " + std::to_string(end) + " ps)");
        if (sumOf(s.busyBy) != s.busy)  // the report's busy_by_category sums to busy_ns
            throw std::runtime_error(std::string("time accounting: busy by kind of work sums to ") +
                                     std::to_string(sumOf(s.busyBy)) + " ps, not busy " + std::to_string(s.busy) + " ps at " + n.name());
    }
    // Rays and frame-buffer traffic must all be delivered; balancing messages
    // (load reports, slides, acks) may still be on their way when the frame ends.
    for (const auto* links : {&links_, &unitLinks_})
        for (const auto& l : *links)
            for (MsgType t : {MsgType::Ray, MsgType::Contributions, MsgType::Credit, MsgType::FbExpect, MsgType::FbDone})
                if (l->inFlight(t))
                    throw std::runtime_error(std::string("conservation: ") + msgTypeName(t) + " messages left on " +
                                             l->name());
    if (relay_ && relay_->inFlight())
        throw std::runtime_error("conservation: " + std::to_string(relay_->inFlight()) + " express rays still in the relay");
    // Ownership: along the axis, neighbours' faces meet, except where a slab is
    // being handed over (a slide still on the link between them).
    const int ax = columns_.axis;
    for (const Node& n : nodes_) {
        const Box& b = n.region().box();
        if (!(b.hi[ax] - b.lo[ax] >= minThickness_ * (1 - 1e-9)))
            throw std::runtime_error(std::string("guard: box thinner than the minimum at ") + n.name());
        const Cell up = neighbour(n.cell(), dirOf(ax, +1));
        if (!inMesh(up, cfg_.dims) || nodes_[nodeIndex(up)].region().box().lo[ax] == b.hi[ax]) continue;
        const Link* l1 = meshLink(nodeIndex(n.cell()), dirOf(ax, +1));
        const Link* l2 = meshLink(nodeIndex(up), dirOf(ax, -1));
        if (!l1->inFlight(MsgType::Slide) && !l2->inFlight(MsgType::Slide))
            throw std::runtime_error(std::string("ownership: a gap or overlap above ") + n.name());
    }
}

}  // namespace rt
