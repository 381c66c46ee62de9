#include "balance/move_forecast.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <queue>
#include <stdexcept>
#include <utility>

#include "base/mesh_geometry.h"
#include "channel/message.h"

namespace rt {

namespace {

// What a slab [a, b] of one column carries: the objects whose bounds reach
// into it, and their bytes. From the scene's objects where the forecast has
// them (each object counted once, as splitObjects gives it), else from the
// boxes of the frame before (each box's count spread evenly along it, so an
// object that reaches into two boxes counts in both).
class SlabContents {
public:
    struct Box {  // a box of the frame before, along the axis, and its objects
        double lo = 0, hi = 0, objects = 0, bytesEach = kSlabObjectBytes;
    };
    explicit SlabContents(std::vector<Box> boxes) : boxes_(std::move(boxes)) {}
    // The objects' extents along the axis (lo, hi, bytes).
    void setObjects(std::vector<std::array<double, 3>> extents) {
        byLo_ = byHi_ = std::move(extents);
        std::sort(byLo_.begin(), byLo_.end(), [](const auto& x, const auto& y) { return x[0] < y[0]; });
        std::sort(byHi_.begin(), byHi_.end(), [](const auto& x, const auto& y) { return x[1] < y[1]; });
        bytesAboveLo_.assign(byLo_.size() + 1, 0.0);  // [i]: the bytes of byLo_[i ..)
        for (size_t i = byLo_.size(); i-- > 0;) bytesAboveLo_[i] = bytesAboveLo_[i + 1] + byLo_[i][2];
        bytesBelowHi_.assign(byHi_.size() + 1, 0.0);  // [i]: the bytes of byHi_[.. i)
        for (size_t i = 0; i < byHi_.size(); ++i) bytesBelowHi_[i + 1] = bytesBelowHi_[i] + byHi_[i][2];
        total_ = bytesAboveLo_[0];
        scene_ = true;
    }
    std::pair<double, double> in(double a, double b) const {  // objects, bytes
        if (scene_) {
            // Every object but those ending below a and those starting above b.
            const size_t below = size_t(std::lower_bound(byHi_.begin(), byHi_.end(), a, [](const auto& x, double v) { return x[1] < v; }) - byHi_.begin());
            const size_t above = size_t(byLo_.end() - std::upper_bound(byLo_.begin(), byLo_.end(), b, [](double v, const auto& x) { return v < x[0]; }));
            const double objects = double(byLo_.size()) - double(below) - double(above);
            return {objects, total_ - bytesBelowHi_[below] - bytesAboveLo_[byLo_.size() - above]};
        }
        double objects = 0, bytes = 0;
        for (const Box& box : boxes_) {
            const double overlap = std::min(b, box.hi) - std::max(a, box.lo);
            if (!(overlap > 0) || !(box.hi > box.lo)) continue;
            const double share = box.objects * overlap / (box.hi - box.lo);
            objects += share;
            bytes += share * box.bytesEach;
        }
        return {objects, bytes};
    }
    const std::vector<Box>& boxes() const { return boxes_; }

private:
    std::vector<Box> boxes_;
    bool scene_ = false;
    std::vector<std::array<double, 3>> byLo_, byHi_;
    std::vector<double> bytesAboveLo_, bytesBelowHi_;
    double total_ = 0;
};

// One column's handovers as the nodes make them (BalanceAgent::startAt,
// giveToStartTarget, tookSlab), event by event: each node gives a slab
// towards its targets as far as its box allows (leaving it the minimum
// thickness) and, each time it takes a slab, gives again; it does one
// thing at a time. A give costs the giver its send and a grid update per
// object moved, then the slab's latency and wire time; the taker its
// receive (and its acknowledgement's send) and the same updates. So a
// plane that moves across k boxes waits for the planes below it, and the
// objects it carries are updated at every box they pass. The rays the
// nodes trace meanwhile are not in it.
class ColumnHandovers {
public:
    struct Costs {
        double send, recv, update, latency, psPerByte, minThickness;  // ps, and ps a byte
    };
    ColumnHandovers(const SlabContents& contents, const Costs& k) : contents_(contents), k_(k) {}

    // When each node's faces are at their targets (or as near as the boxes
    // allow), in ps from the move's start: 0 for a node whose faces stay.
    std::vector<double> run(const std::vector<double>& from, const std::vector<double>& to) const {
        const std::vector<SlabContents::Box>& boxes = contents_.boxes();
        const size_t n = boxes.size();
        std::vector<Node> nodes(n);
        for (size_t j = 0; j < n; ++j) {
            Node& d = nodes[j];
            d.lo = j ? from[j - 1] : boxes[j].lo;
            d.hi = j + 1 < n ? from[j] : boxes[j].hi;
            d.toLo = j ? to[j - 1] : std::nan("");
            d.toHi = j + 1 < n ? to[j] : std::nan("");
            d.startLo = j > 0;
            d.startHi = j + 1 < n;
        }
        Queue arriving;
        for (size_t j = 0; j < n; ++j) act(nodes, j, arriving);
        while (!arriving.empty()) {
            const Slab s = arriving.top();
            arriving.pop();
            Node& d = nodes[s.to];
            d.free = std::max(d.free, s.at) + k_.recv + k_.send + s.objects * k_.update;
            (s.fromBelow ? d.lo : d.hi) = s.face;
            d.ready = d.free;
            d.startLo = d.startLo || (s.to > 0 && d.toLo > d.lo);
            d.startHi = d.startHi || (s.to + 1 < n && d.toHi < d.hi);
            act(nodes, s.to, arriving);
        }
        std::vector<double> ready;
        for (const Node& d : nodes) ready.push_back(d.ready);
        return ready;
    }

private:
    struct Node {
        double lo = 0, hi = 0, toLo = 0, toHi = 0, free = 0;
        double ready = 0;  // when a face of it last moved
        bool startLo = false, startHi = false;
    };
    struct Slab {
        double at;
        size_t to;
        double face, objects;
        bool fromBelow;
        bool operator>(const Slab& o) const { return at > o.at || (at == o.at && to > o.to); }
    };
    using Queue = std::priority_queue<Slab, std::vector<Slab>, std::greater<>>;

    // What node j gives while a face of it has a target beyond it.
    void act(std::vector<Node>& nodes, size_t j, Queue& arriving) const {
        Node& d = nodes[j];
        while (d.startLo || d.startHi) {
            if (std::exchange(d.startLo, false) && d.toLo > d.lo) {
                const double face = std::min(d.toLo, d.hi - k_.minThickness);
                if (face > d.lo) {
                    give(d, j - 1, d.lo, face, false, arriving);
                    d.lo = face;
                    d.ready = d.free;
                    continue;
                }
            }
            if (std::exchange(d.startHi, false) && d.toHi < d.hi) {
                const double face = std::max(d.toHi, d.lo + k_.minThickness);
                if (face < d.hi) {
                    give(d, j + 1, face, d.hi, true, arriving);
                    d.hi = face;
                    d.ready = d.free;
                }
            }
        }
    }
    void give(Node& d, size_t to, double a, double b, bool fromBelow, Queue& arriving) const {
        const auto [objects, bytes] = contents_.in(a, b);
        d.free += k_.send + objects * k_.update;
        arriving.push({d.free + k_.latency + bytes * k_.psPerByte, to, fromBelow ? a : b, objects, fromBelow});
    }

    const SlabContents& contents_;
    Costs k_;
};

// Each column's contents: its boxes in frame `r` and, with the scene's
// objects, those whose bounds reach into the column's cross-section.
std::vector<SlabContents> columnContents(const FrameState& r, const ColumnGeometry& g, const std::vector<Shape>* objects) {
    const int ax = g.axis;
    std::vector<std::vector<SlabContents::Box>> boxes(size_t(g.count()), std::vector<SlabContents::Box>(size_t(g.length())));
    std::vector<rt::Box> section(size_t(g.count()));  // the column's cross-section (its boxes share it)
    for (const NodeFrameState& node : r.nodes) {
        const size_t c = size_t(g.columnOf(node.cell));
        SlabContents::Box& b = boxes[c][size_t(node.cell[size_t(ax)])];
        b = {node.box.lo[ax], node.box.hi[ax], double(node.objects), b.bytesEach};
        if (node.objectBytes > 0 && node.objects > 0) b.bytesEach = node.objectBytes / double(node.objects);
        section[c] = node.box;
    }
    std::vector<SlabContents> out;
    for (auto& b : boxes) out.emplace_back(std::move(b));
    if (!objects) return out;
    // (Columns (i, j) share their extent across the axis with every column
    // of the same i, and of the same j: an object's columns are a range of
    // each.)
    const int U = g.dims[size_t(g.u)], V = g.dims[size_t(g.v)];
    std::vector<std::vector<std::array<double, 3>>> extents(out.size());
    for (const Shape& s : *objects) {
        const rt::Box sb = s.bounds();
        const double bytes = double(objectBytes(s));
        for (int j = 0; j < V; ++j) {
            const rt::Box& y = section[size_t(g.indexOf(0, j))];
            if (!(sb.lo[g.v] <= y.hi[g.v] && y.lo[g.v] <= sb.hi[g.v])) continue;
            for (int i = 0; i < U; ++i) {
                const rt::Box& x = section[size_t(g.indexOf(i, j))];
                if (sb.lo[g.u] <= x.hi[g.u] && x.lo[g.u] <= sb.hi[g.u]) extents[size_t(g.indexOf(i, j))].push_back({sb.lo[ax], sb.hi[ax], bytes});
            }
        }
    }
    for (size_t c = 0; c < out.size(); ++c) out[c].setObjects(std::move(extents[c]));
    return out;
}

}  // namespace

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

InnerPlanes facesInPlaceNs(const FrameState& r, const MachineConfig& m, const InnerPlanes& from, const InnerPlanes& to,
                           const std::vector<Shape>* objects) {
    const ColumnGeometry g(m.balance.axis, m.dims);
    const auto ofThisMesh = [&](const InnerPlanes& p) {
        return p.size() == size_t(g.count()) &&
               std::all_of(p.begin(), p.end(), [&](const std::vector<double>& c) { return c.size() + 1 == size_t(g.length()); });
    };
    const bool nodesFit = std::all_of(r.nodes.begin(), r.nodes.end(), [&](const NodeFrameState& n) {
        for (size_t d = 0; d < 3; ++d)
            if (n.cell[d] < 0 || n.cell[d] >= m.dims[d]) return false;
        return true;
    });
    if (!ofThisMesh(from) || !ofThisMesh(to) || !nodesFit) throw std::invalid_argument("facesInPlaceNs: planes or a frame of another mesh");
    const LinkParams& l = m.link;
    const Costs& k = m.costs;
    const double handling = m.hopsByLinks ? 0.0 : 1.0;
    const std::vector<SlabContents> contents = columnContents(r, g, objects);
    InnerPlanes ready(contents.size(), std::vector<double>(size_t(g.length()), 0.0));
    for (size_t c = 0; c < from.size() && c < to.size() && c < contents.size(); ++c) {
        if (from[c] == to[c]) continue;
        const auto& boxes = contents[c].boxes();
        const double length = boxes.back().hi - boxes.front().lo;
        // The handling and the grid updates at the nodes' speed, as the
        // nodes charge them (cost_model.h; per-node overrides aside).
        const ColumnHandovers::Costs costs{handling * double(k.send) / m.speed,
                                           handling * double(k.recv) / m.speed,
                                           double(m.balance.rebuildCost) / m.speed,
                                           double(l.latency),
                                           1e12 / l.bandwidth,
                                           m.balance.minThickness * length / g.length()};  // (minThicknessOf: the boxes cover the world)
        ready[c] = ColumnHandovers(contents[c], costs).run(from[c], to[c]);
        for (double& t : ready[c]) t /= 1000.0;
    }
    return ready;
}

}  // namespace rt
