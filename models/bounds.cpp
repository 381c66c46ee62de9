#include "bounds.h"

#include <algorithm>
#include <map>

namespace rt {

Bounds renderTimeBounds(const MachineResult& r, const MachineConfig& cfg) {
    Bounds b;
    const int ax = cfg.balance.axis;
    Picos total = 0;
    std::map<std::pair<int, int>, Picos> columns;  // by the coordinates on the other two axes
    for (size_t i = 0; i < r.nodes.size(); ++i) {
        total += r.nodes[i].busy;
        const Cell& c = r.cells[i];
        columns[{c[(ax + 1) % 3], c[(ax + 2) % 3]}] += r.nodes[i].busy;
    }
    if (!r.nodes.empty()) b.perfect = total / r.nodes.size();
    for (const auto& [where, busy] : columns) b.column = std::max(b.column, busy / Picos(cfg.dims[ax]));
    for (const FrameBufferUnitReport& u : r.frameBuffer) b.frameBuffer = std::max(b.frameBuffer, u.stats.busy);
    return b;
}

}  // namespace rt
