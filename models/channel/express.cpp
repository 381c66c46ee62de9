#include "channel/express.h"

#include <algorithm>

namespace rt {

ExpressRoutes::ExpressRoutes(std::array<int, 3> dims, std::vector<ExpressNode> nodes) : dims_(dims), nodes_(std::move(nodes)) {
    soonestHop_ = ~Picos(0);
    for (const ExpressNode& n : nodes_)
        for (const ExpressLink& l : n.out)
            if (l.link) soonestHop_ = std::min(soonestHop_, l.hop());
}

void ExpressRoutes::countOnLinks() {
    for (ExpressNode& n : nodes_)
        for (ExpressLink& l : n.out)
            if (l.rays) {
                l.link->countExpress(kHeaderBytes + kRayBytes, l.rays);
                l.rays = 0;
            }
}

bool ExpressRoutes::route(const Cell& from, int dir, RayJob& job, Picos now, Route& r, std::vector<ExpressHop>& hops) const {
    Cell at = neighbour(from, dir);
    size_t cur = indexOf(at);
    Route path;
    path.first = uint32_t(hops.size());
    RayJob probe = job;
    double t0 = job.t0;  // where the ray enters `cur`
    Picos reach = now + nodes_[indexOf(from)].out[size_t(dir)].hop();  // the soonest it reaches `cur`
    for (;;) {
        // What the box's node would do with it (Node::step): route it on if
        // the box does not own t0; else trace it (an empty box's: it ends
        // there only if it reaches its light there) and send it on by the
        // face it leaves by.
        const ExpressNode& n = nodes_[cur];
        if (!n.empty && !(n.through && through_)) break;
        if (n.through && n.busyAt(reach)) break;  // busy then: its node takes it
        const Box& box = n.box;
        const BoxSlabs s = boxSlabs(probe.ray, box);
        int d = routeRay(probe, s, box);
        Picos step = n.pass;
        if (d < 0) {
            if (n.empty) {
                if (probe.tEnd <= s.span.hi) break;  // it ends in this box: its node takes it
                probe.t0 = s.span.hi;
            } else if (!through_->passes(cur, probe, s.span.hi, step)) {
                break;  // it hits or ends in this box: its node takes it
            }
            const auto [axis, sign] = s.exitFace(probe.ray);
            if (axis < 0) break;  // (its node says what is wrong)
            d = dirOf(axis, sign);
        }
        const Cell next = neighbour(at, d);
        if (!inMesh(next, dims_)) break;  // it leaves the world here: its node sends the background
        hops.push_back({uint32_t(cur), int8_t(d), step, t0});
        reach += step + n.out[size_t(d)].hop();
        t0 = probe.t0;
        at = next;
        cur = indexOf(at);
    }
    path.skipped = uint32_t(hops.size()) - path.first;
    if (path.skipped == 0) return false;
    job.t0 = t0;
    r = path;
    return true;
}

}  // namespace rt
