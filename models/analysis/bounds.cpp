#include "analysis/bounds.h"

#include <algorithm>
#include <vector>

namespace rt {

Bounds renderTimeBounds(const MachineResult& r, const MachineConfig& cfg) {
    Bounds b;
    const ColumnGeometry g(cfg.balance.axis, cfg.dims);
    Picos total = 0;
    std::vector<Picos> columns(size_t(g.count()), 0);
    for (size_t i = 0; i < r.nodes.size(); ++i) {
        total += r.nodes[i].busy;
        columns[size_t(g.columnOf(r.cells[i]))] += r.nodes[i].busy;
    }
    if (!r.nodes.empty()) b.perfect = total / r.nodes.size();
    for (Picos busy : columns) b.column = std::max(b.column, busy / Picos(g.length()));
    for (const FrameBufferUnitReport& u : r.frameBuffer) b.frameBuffer = std::max(b.frameBuffer, u.stats.busy);
    return b;
}

}  // namespace rt
