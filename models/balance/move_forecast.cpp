#include "balance/move_forecast.h"

#include <algorithm>
#include <cmath>

#include "base/mesh_geometry.h"

namespace rt {

double moveNs(const FrameState& r, const MachineConfig& m, const InnerPlanes& from, const InnerPlanes& to) {
    const ColumnGeometry g(m.balance.axis, m.dims);
    const int ax = g.axis, n = g.length();
    // Each column's boxes along the axis and their objects.
    std::vector<std::vector<std::array<double, 3>>> boxes(size_t(g.count()), std::vector<std::array<double, 3>>(size_t(n)));
    for (const NodeFrameState& node : r.nodes)
        boxes[size_t(g.columnOf(node.cell))][size_t(node.cell[size_t(ax)])] = {node.box.lo[ax], node.box.hi[ax],
                                                                              double(node.objects)};
    const LinkParams& l = m.link;
    const Costs& k = m.costs;
    const double hop = double(l.latency) + (m.hopsByLinks ? 0.0 : double(k.send + k.recv));  // ps
    const double perObject = kSlabObjectBytes / l.bandwidth * 1e12 + 2.0 * double(m.balance.rebuildCost);  // ps
    double longest = 0;
    for (size_t c = 0; c < from.size() && c < to.size(); ++c)
        for (size_t i = 0; i < from[c].size() && i < to[c].size(); ++i) {
            const double a = std::min(from[c][i], to[c][i]), b = std::max(from[c][i], to[c][i]);
            if (!(b > a)) continue;
            double hops = 0, objects = 0;
            for (const auto& [lo, hi, count] : boxes[c]) {
                const double overlap = std::min(b, hi) - std::max(a, lo);
                if (!(overlap > 0) || !(hi > lo)) continue;
                ++hops;
                objects += count * overlap / (hi - lo);
            }
            // (an object travels from where it is to its new box: on average half the chain)
            longest = std::max(longest, hops * hop + objects * 0.5 * (hops + 1) * perObject);
        }
    return longest / 1000.0;
}

}  // namespace rt
