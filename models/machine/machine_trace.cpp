// The machine's VCD (--vcd; doc/waveforms.md): per traced node
// (all, unless --trace-nodes) busy, wait, queue and load, and under it its
// traced links (its own, and those --trace-links names); the frame-buffer
// units; every boundary when balancing. The header is written before the
// run, the changes as it goes (vcd_stream.h).
#include <algorithm>
#include <set>

#include "machine/machine.h"
#include "trace/trace_writer.h"

namespace rt {

void Machine::setupTraces() {
    vcd_ = std::make_unique<VcdStream>();
    std::vector<NodeTrace> traces(nodes_.size());
    traceNodes(traces);
    traceUnits();
    if (cfg_.balance.policy != "none") traceBoundaries(traces);
    for (size_t i = 0; i < nodes_.size(); ++i) nodes_[i].enableTrace(traces[i]);
    vcd_->setHorizon([this] { return traceHorizon(); });
    vcd_->open(cfg_.vcdPath, cfg_.traceFrom, cfg_.traceTo, cfg_.vcdName.empty() ? cfg_.vcdPath : cfg_.vcdName);
}

// Each traced node's signals, then its traced links'; a traced frame-buffer
// port's channels, one per unit, share its signals.
void Machine::traceNodes(std::vector<NodeTrace>& traces) {
    using K = VcdStream::Kind;
    VcdStream& v = *vcd_;
    std::vector<bool> tracedNode(nodes_.size(), cfg_.traceNodes.empty());
    for (const Cell& c : cfg_.traceNodes) tracedNode[nodeIndex(c)] = true;
    std::set<std::pair<size_t, int>> links;  // (node, direction; kDirs: its frame-buffer port)
    for (size_t i = 0; i < nodes_.size(); ++i)
        if (tracedNode[i])
            for (int d = 0; d <= kDirs; ++d) links.insert({i, d});
    for (const auto& [c, d] : cfg_.traceLinks)
        for (int e = 0; e <= kDirs; ++e)
            if (d < 0 || d == e) links.insert({nodeIndex(c), e});
    std::vector<LinkTrace> fbTraces(nodes_.size());
    for (size_t i = 0; i < nodes_.size(); ++i) {
        const std::string name = nodeName(nodes_[i].cell());
        NodeTrace& t = traces[i];
        t.vcd = &v;
        if (tracedNode[i]) {
            t.busy = v.declare(name, "busy", K::Bit);
            t.wait = v.declare(name, "wait", K::Bit);
            t.queue = v.declare(name, "queue", K::Integer);
            v.declareLoad(name, t.busy, t.wait);
        }
        for (int d = 0; d <= kDirs; ++d) {
            if (!links.count({i, d})) continue;
            const bool fb = d == kDirs;
            if (!fb && !meshLink(i, d)) continue;  // a mesh face
            const std::string scope = name + "." + (fb ? std::string("fb") : linkSuffix(d));
            LinkTrace lt{&v, v.declare(scope, "wire", fb ? K::Integer : K::Bit), v.declare(scope, "buffered", K::Integer),
                         v.declare(scope, "backlog", K::Integer)};
            if (fb) {
                fbTraces[i] = lt;
            } else {
                Link* l = meshLink(i, d);
                l->setTrace(lt);
                tracedLinks_.push_back(l);
            }
        }
    }
    for (size_t j = 0; j < links_.size(); ++j) {
        const LinkReport& info = linkInfo_[reportOf_[j]];
        if (info.dir >= 0) continue;
        const LinkTrace& lt = fbTraces[nodeIndex(info.from)];
        if (!lt.vcd) continue;
        links_[j]->setTrace(lt);
        tracedLinks_.push_back(links_[j].get());
    }
}

void Machine::traceUnits() {
    using K = VcdStream::Kind;
    for (size_t u = 0; u < units_.size(); ++u) {
        const std::string scope = "frame_buffer.unit_" + std::to_string(u);
        FrameBufferUnit::Trace t{vcd_.get(), vcd_->declare(scope, "busy", K::Bit), vcd_->declare(scope, "contributions", K::Integer)};
        if (u == 0) t.credit = vcd_->declare(scope, "credit", K::Real);  // the share of the frame's credit back
        units_[u].enableTrace(t);
    }
}

// Each boundary: its position and slides, recorded by the node that gives.
void Machine::traceBoundaries(std::vector<NodeTrace>& traces) {
    using K = VcdStream::Kind;
    for (const BoundaryHistory& h : boundaryHistories()) {
        const std::string scope = "boundaries.col_" + std::to_string(h.column[0]) + "_" + std::to_string(h.column[1]) +
                                  "_b" + std::to_string(h.index);
        const int pos = vcd_->declare(scope, "position", K::Real), slides = vcd_->declare(scope, "slides", K::Integer);
        vcd_->setReal(0, pos, h.positions[0].second);
        const size_t below = nodeIndex(columns_.cell(h.column[0], h.column[1], h.index - 1));
        const size_t above = nodeIndex(columns_.cell(h.column[0], h.column[1], h.index));
        traces[below].position[1] = traces[above].position[0] = pos;
        traces[below].slides[1] = traces[above].slides[0] = slides;
    }
}

// Every change before this time is recorded: processes record at their
// own time, never behind the kernel's, and so do links, except those with
// a control lane, which record a message when it is consumed, at times
// from its sending on (Link::traceStart).
Picos Machine::traceHorizon() const {
    Picos h = frameClock();
    for (const Link* l : tracedLinks_)
        if (l->tracesLate()) h = std::min(h, l->oldestSent());
    return h;
}

void Machine::closeTraces() {
    if (!vcd_) return;
    const Picos end = frameEnd();
    vcd_->close(end, stopped() ? "incomplete: " + watchdog_->stall() : "");
    const std::string name = cfg_.vcdName.empty() ? cfg_.vcdPath : cfg_.vcdName;
    gtkw_ = gtkwText(gtkwPathFor(name), name, *vcd_, cfg_.traceFrom, std::min(cfg_.traceTo, end));
}

}  // namespace rt
