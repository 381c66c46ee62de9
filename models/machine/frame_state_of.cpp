#include "machine/frame_state_of.h"

#include <algorithm>

namespace rt {
namespace {


Binned binned(const WorkByPosition& w, double scale) {
    Binned b{w.firstBin(), {}};
    b.values.reserve(w.bins().size());
    for (double v : w.bins()) b.values.push_back(scale == 1 ? v : v / scale);
    return b;
}

// The node's work by position in the report's units: ns per bin, and the
// cuts as running sums of the segments' starts and stops.
WorkAlongAxis workAlongAxis(const BalanceStats& s) {
    WorkAlongAxis w;
    w.axisFrom = s.work.from();
    w.binWidth = s.work.binWidth();
    w.ns = binned(s.work, 1000.0);
    if (!s.within.bins().empty()) w.within = binned(s.within, 1000.0);
    w.faceHandlingNs = inNs(s.faceCost);
    w.faceCrossings = s.faceCrossings;
    for (int up = 0; up < 2; ++up) {
        Binned& c = w.cuts[size_t(up)];
        c.firstBin = s.spans[size_t(up)].firstBin();
        double running = 0;
        for (double b : s.spans[size_t(up)].bins()) c.values.push_back(running += b);
    }
    for (int d = 0; d < 6; ++d)
        if (!s.lateral[size_t(d)].bins().empty()) w.lateral[size_t(d)] = binned(s.lateral[size_t(d)], 1);
    return w;
}

}  // namespace

FrameState frameStateOf(const MachineResult& r, const MachineConfig& cfg) {
    FrameState f;
    f.dims = cfg.dims;
    f.axis = cfg.balance.axis;
    f.renderTimeNs = inNs(r.renderTime);
    for (size_t i = 0; i < r.nodes.size(); ++i) {
        const NodeStats& s = r.nodes[i];
        NodeFrameState n;
        n.cell = r.cells[i];
        n.box = r.boxes[i];
        n.objects = r.objectsPerNode[i];
        n.objectBytes = double(r.objectBytesPerNode[i]);
        if (i < r.grids.size() && r.grids[i]) {
            n.gridCells = r.grids[i]->cells;
            n.gridSpan = r.grids[i]->span;
        }
        n.busyNs = inNs(s.busy);
        if (!s.balance.work.bins().empty()) n.work = workAlongAxis(s.balance);
        f.raysPassed += s.raysPassed;
        f.nodes.push_back(std::move(n));
    }
    for (const BoundaryHistory& h : r.boundaries) {
        BoundaryState b{h.column, h.index, {}};
        for (const auto& [t, x] : h.positions) b.history.push_back({inNs(t), x});
        f.boundaries.push_back(std::move(b));
    }
    for (const LinkReport& l : r.links)
        if (l.dir >= 0) {  // (the frame buffer's ports aside)
            const LinkStats s = l.stats();  // (made from the report's counts: once)
            f.rayWireNs += inNs(s.wire[size_t(MsgType::Ray)]);
            f.busiestLinkWireNs = std::max(f.busiestLinkWireNs, inNs(s.wireBusy()));
        }
    return f;
}

}  // namespace rt
