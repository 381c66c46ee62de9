#include "balance/move_forecast.h"

#include <algorithm>
#include <cmath>

#include "base/mesh_geometry.h"

namespace rt {

double moveNs(const FrameState& r, const MachineConfig& m, const InnerPlanes& from, const InnerPlanes& to) {
    const ColumnGeometry g(m.balance.axis, m.dims);
    const int ax = g.axis, n = g.length();
    // Each column's boxes along the axis, their objects and their mean size.
    std::vector<std::vector<std::array<double, 4>>> boxes(size_t(g.count()), std::vector<std::array<double, 4>>(size_t(n)));
    for (const NodeFrameState& node : r.nodes) {
        const double bytes = node.objectBytes > 0 && node.objects > 0 ? node.objectBytes / double(node.objects) : kSlabObjectBytes;
        boxes[size_t(g.columnOf(node.cell))][size_t(node.cell[size_t(ax)])] = {node.box.lo[ax], node.box.hi[ax],
                                                                              double(node.objects), bytes};
    }
    const LinkParams& l = m.link;
    const Costs& k = m.costs;
    const double hop = double(l.latency) + (m.hopsByLinks ? 0.0 : double(k.send + k.recv));  // ps
    const double updates = 2.0 * double(m.balance.rebuildCost);  // ps an object, the giver's and the taker's
    double longest = 0;
    for (size_t c = 0; c < from.size() && c < to.size(); ++c)
        for (size_t i = 0; i < from[c].size() && i < to[c].size(); ++i) {
            const double a = std::min(from[c][i], to[c][i]), b = std::max(from[c][i], to[c][i]);
            if (!(b > a)) continue;
            double hops = 0, objectTime = 0;  // ps: each object's wire time and updates once
            for (const auto& [lo, hi, count, bytes] : boxes[c]) {
                const double overlap = std::min(b, hi) - std::max(a, lo);
                if (!(overlap > 0) || !(hi > lo)) continue;
                ++hops;
                objectTime += count * overlap / (hi - lo) * (bytes / l.bandwidth * 1e12 + updates);
            }
            // (an object travels from where it is to its new box: on average half the chain)
            longest = std::max(longest, hops * hop + objectTime * 0.5 * (hops + 1));
        }
    return longest / 1000.0;
}

}  // namespace rt
