#include "balance/move_forecast.h"

#include <algorithm>
#include <cmath>

#include "base/mesh_geometry.h"

namespace rt {

double chainPs(const std::vector<BoxPass>& boxes, double a, double b, double hopPs) {
    if (a > b) std::swap(a, b);
    if (!(b > a)) return 0;
    double hops = 0, objectTime = 0;  // ps: each object's wire time and updates once
    for (const BoxPass& box : boxes) {
        const double overlap = std::min(b, box.hi) - std::max(a, box.lo);
        if (!(overlap > 0) || !(box.hi > box.lo)) continue;
        hops += std::max(1.0, box.boxes * overlap / (box.hi - box.lo));
        objectTime += box.passPs * overlap / (box.hi - box.lo);
    }
    // (an object travels from where it is to its new box: on average half the chain)
    return hops * hopPs + objectTime * 0.5 * (hops + 1);
}

double moveNs(const FrameState& r, const MachineConfig& m, const InnerPlanes& from, const InnerPlanes& to) {
    const ColumnGeometry g(m.balance.axis, m.dims);
    const int ax = g.axis, n = g.length();
    const LinkParams& l = m.link;
    const Costs& k = m.costs;
    // The handling and the grid updates at the nodes' speed, as the nodes
    // charge them (cost_model.h; per-node overrides aside).
    const double hop = double(l.latency) + (m.hopsByLinks ? 0.0 : double(k.send + k.recv) / m.speed);  // ps
    const double updates = 2.0 * double(m.balance.rebuildCost) / m.speed;  // ps an object, the giver's and the taker's
    // Each column's boxes along the axis, and what passing their objects on costs.
    std::vector<std::vector<BoxPass>> boxes(size_t(g.count()), std::vector<BoxPass>(size_t(n), BoxPass{0, 0, 0, 1}));
    for (const NodeFrameState& node : r.nodes) {
        const double bytes = node.objectBytes > 0 && node.objects > 0 ? node.objectBytes / double(node.objects) : kSlabObjectBytes;
        boxes[size_t(g.columnOf(node.cell))][size_t(node.cell[size_t(ax)])] = {
            node.box.lo[ax], node.box.hi[ax], double(node.objects) * (bytes / l.bandwidth * 1e12 + updates), 1};
    }
    double longest = 0;
    for (size_t c = 0; c < from.size() && c < to.size(); ++c)
        for (size_t i = 0; i < from[c].size() && i < to[c].size(); ++i)
            longest = std::max(longest, chainPs(boxes[c], from[c][i], to[c][i], hop));
    return longest / 1000.0;
}

}  // namespace rt
