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

bool ExpressRoutes::route(const Cell& from, int dir, RayJob& job, Route& r, std::vector<ExpressHop>& hops) const {
    Cell at = neighbour(from, dir);
    size_t cur = indexOf(at);
    Route path;
    path.first = uint32_t(hops.size());
    RayJob probe = job;
    double t0 = job.t0;  // where the ray enters `cur`
    while (nodes_[cur].empty) {
        // What the empty box's node would do with it (Node::step): route it
        // on if the box does not own t0; else "trace" it (no object: it
        // ends here only if it reaches its light here) and send it on by
        // the face it leaves by.
        const Box& box = nodes_[cur].box;
        const BoxSlabs s = boxSlabs(probe.ray, box);
        int d = routeRay(probe, s, box);
        if (d < 0) {
            if (probe.tEnd <= s.span.hi) break;  // it ends in this box: its node takes it
            probe.t0 = s.span.hi;
            const auto [axis, step] = s.exitFace(probe.ray);
            if (axis < 0) break;  // (its node says what is wrong)
            d = dirOf(axis, step);
        }
        const Cell next = neighbour(at, d);
        if (!inMesh(next, dims_)) break;  // it leaves the world here: its node sends the background
        hops.push_back({uint32_t(cur), int8_t(d)});
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
