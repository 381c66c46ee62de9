// The balancing protocol, the node's side (doc/balancing.md): the agent
// (balance_agent.h) runs the rounds and decides; the node measures,
// carries the messages, hands over and takes slabs (slab.h), and tells the
// guard its links' timing.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "node/node.h"
#include "grid.h"
#include "balance/slab.h"

namespace rt {

void Node::rebuild(const Box& box, std::vector<Shape> objects) {
    for (int a = 0; a < 3; ++a)
        if (!(box.lo[a] < box.hi[a])) {
            char buf[256];
            std::snprintf(buf, sizeof buf, "%s: empty box on axis %d: [%.17g, %.17g] at %llu ps", name(), a, box.lo[a],
                          box.hi[a], (unsigned long long)now_);
            throw std::logic_error(buf);
        }
    std::sort(objects.begin(), objects.end(), [](const Shape& a, const Shape& b) { return a.id < b.id; });
    region_ = std::make_unique<Region>(box, std::move(objects), AccelKind::Grid);
    if (sample_) noteOccupied();
}

void Node::setSample(bool gathers, std::vector<int> beside, std::vector<double> faces) {
    sample_ = SampleSetup{gathers, std::move(beside), std::move(faces)};
    noteOccupied();
}

// `sample` begins: the gather starts once the node has generated its
// sample's primary rays (first in its queue). Their rays go ahead of the
// rest's in every queue they reach, and the gather's messages follow them
// on the same links (doc/balancing.md, "One frame: sample, then split").
void Node::sampleBegins() {
    sample_->trigger = stats_.counters.primaryRays + input_.primaries().sampleLeft();
    sample_->armed = true;
    sampleGenerated();
}

void Node::sampleGenerated() {
    if (!sample_->armed || stats_.counters.primaryRays < sample_->trigger) return;
    sample_->armed = false;
    balance_->sampleReady(now_);
}

// An ended ray's credit (k shares of 2^-e), kept to go back to the frame
// buffer; under --sample-end credit a ray of the sample's apart
// (doc/balancing.md, "When the sample is done").
void Node::giveBack(const Work& w, int e, uint64_t k) {
    if (sampleCredit() && sampleRay(w.job)) fbOut_.addSampleCredit(e, k);
    else fbOut_.addCredit(e, k);
}

void Node::noteOccupied() {
    const Box part = UniformGrid::occupiedPart(region_->objects(), region_->box());
    occupied_ = {part.lo[params_.balance.axis], part.hi[params_.balance.axis]};
}

// With targets for the frame's start, the node's primary rays are those of
// its target box: it generates them once its faces are there (else it would
// trace them where it does not yet have the objects, or pass them on).
bool Node::holdsPrimaries() {
    if (!startTargets_) return false;
    const int ax = params_.balance.axis;
    const Box& b = region_->box();
    const auto [lo, hi] = *startTargets_;
    if ((std::isfinite(lo) && b.lo[ax] != lo) || (std::isfinite(hi) && b.hi[ax] != hi)) return true;
    startTargets_.reset();
    return false;
}

// The step's share in the faces along the axis, for `resplit`'s next
// planes: the ray's crossings of those faces (in from a column neighbour, out
// to one) and what handling them cost here, and the span it was traced over.
FaceCrossings Node::axialFaces(const Work& w, const BusyParts& parts, const TracedSpan& span) const {
    const int ax = params_.balance.axis;
    FaceCrossings f{span.from, span.to, 0, 0};
    if (w.from >= 0 && dirAxis(w.from) == ax) {
        ++f.crossings;
        if (w.fromLink) f.cost += parts[kReceive];
    }
    size_t axial = 0;
    for (const auto& [d, m] : outbox_) axial += d >= 0 && d < 6 && dirAxis(d) == ax && m.type == MsgType::Ray;
    if (span.exit >= 0 && outLinks_[size_t(span.exit)]) {
        if (dirAxis(span.exit) == ax) ++f.crossings;
        else f.lateral = span.exit;
    }
    if (axial) f.cost += parts[kSend] * Picos(axial) / Picos(outbox_.size());
    // Entered by a face along the axis (over a link, or generated there) or left by one?
    const Box& b = region_->box();
    const double eps = 1e-9 * std::max(1.0, b.hi[ax] - b.lo[ax]);
    const bool in = (w.from >= 0 && dirAxis(w.from) == ax) || std::abs(span.from - b.lo[ax]) <= eps ||
                    std::abs(span.from - b.hi[ax]) <= eps;
    const bool out = span.exit >= 0 && dirAxis(span.exit) == ax;
    if (!in && !out)
        for (int k = 0; k < kPrimitiveKinds; ++k) f.within += parts[size_t(k)];
    return f;
}

// `sample`: a sample ray's step, each part of its work where it happened:
// its generation where it started (that stays with the node that generates
// it), its shading at its hit, its tests and voxel steps in the middle of the
// part of its segment where the box's objects are (the grid spans only
// that: UniformGrid::occupiedPart), the rest in the middle of its segment.
void Node::recordSample(const BusyParts& parts, const TracedSpan& span, int from) {
    Picos tests = parts[kVoxelSteps], rest = sumOf(parts) - parts[kRayGeneration] - parts[kShading];
    for (int k = 0; k < kPrimitiveKinds; ++k) tests += parts[size_t(k)];
    rest -= tests;
    const double lo = std::min(span.from, span.to), hi = std::max(span.from, span.to);
    if (params_.balance.sampleLinks) {  // where its segment runs along the axis (ColumnSample::cross)
        const int ax = params_.balance.axis;
        const Box& box = region_->box();
        const double eps = 1e-9 * std::max(1.0, box.hi[ax] - box.lo[ax]);
        if (std::isfinite(lo) && std::isfinite(hi)) balance_->recordCrossing(lo, hi, hi >= box.hi[ax] - eps);
    }
    const double a = std::max(lo, occupied_[0]);
    const double b = std::min(hi, occupied_[1]);
    if (parts[kRayGeneration]) balance_->recordSample(span.from, parts[kRayGeneration]);
    if (parts[kShading]) balance_->recordSample(span.to, parts[kShading]);
    if (tests) balance_->recordSample(a <= b ? 0.5 * (a + b) : span.where, tests);
    if (rest) balance_->recordSample(span.where, rest);
    // Its crossings of the column's sides to and from the columns beside,
    // where they happened, each at what a pass costs (passCost).
    // (passCost reads every link: only for a step that crosses a side.)
    if (sample_->beside.empty()) return;
    const int ax = params_.balance.axis, out = span.exit;
    const bool in = from >= 0 && dirAxis(from) != ax, leaves = out >= 0 && dirAxis(out) != ax && outLinks_[size_t(out)];
    if (!in && !leaves) return;
    const double pass = passCost();
    if (in) balance_->recordSide(span.from, pass);
    if (leaves) balance_->recordSide(span.to, pass);
}

// At the end of each interval: the agent records the node's load over it,
// and reports and decides with each neighbour as far as the lockstep allows.
void Node::closeInterval() {
    if (progress_) progress_->poll();
    balance_->closeInterval(now_, stats_.busy, stats_.wait, input_.depth(now_));
}

void Node::sendReport(int side, Message m) { sendOn(sideDir(side), std::move(m)); }

void Node::sendOn(int dir, Message m) {
    outbox_.push_back({dir, std::move(m)});
    traceState(true, false);
    finishControlStep(0, 0);
}

void Node::control(Message& m, int fromDir) {
    const int side = dirStep(fromDir);  // the neighbour is below (-1) or above (+1) along the axis
    traceState(true, false);
    if (m.type == MsgType::Planes) {  // (from above, or from a neighbouring column)
        finishControlStep(1, 0);
        balance_->onPlanes(fromDir, m, now_);
        return;
    }
    if (dirAxis(fromDir) != params_.balance.axis)
        throw std::logic_error(std::string(name()) + ": control message off the progress axis");
    if (m.type == MsgType::Sample) {
        finishControlStep(1, 0);
        balance_->onSample(m, now_);
    } else if (m.type == MsgType::LoadReport) {
        finishControlStep(1, 0);
        balance_->onReport(side, m, now_);
    } else if (m.type == MsgType::Slide) {
        input_.primaries().take(m.body().primaries);
        takeSlab(side, m.body().boundary, std::move(m.body().objects));
    } else if (m.type == MsgType::Ack) {
        ++stats_.acks;
        finishControlStep(1, 0);
    }
}

// The heavier node gives the slab between its face on `side` and
// `boundary`, with the objects that overlap it, in one message. From now on
// rays that reach it for the slab are forwarded to the neighbour
// (route.h); the link is FIFO, so they arrive after the slide.
void Node::giveSlab(int side, double boundary) {
    const int ax = params_.balance.axis;
    const Box own = withFace(region_->box(), ax, side, boundary);
    ObjectSplit objects = splitObjects(region_->objects(), slabOf(region_->box(), ax, side, boundary), own, margin_);
    const size_t moved = objects.give.size();
    stats_.slides.push_back({now_, side, boundary, moved});
    const size_t face = side > 0 ? 1 : 0;
    if (trace_.position[face] >= 0) {  // the boundary's signals, if traced
        trace_.vcd->setReal(now_, trace_.position[face], boundary);
        trace_.vcd->step(now_, trace_.slides[face], 1);
    }
    stats_.objectsSent += moved;
    Message slide = Message::slide(boundary, std::move(objects.give));
    // `sample`: the primary rays that start in the slab go with it (in
    // the other policies a node generates the rays the host gave it).
    if (sample_) slide.body().primaries = input_.handOver(params_.camera, params_.world, ax, boundary, side > 0);
    outbox_.push_back({sideDir(side), std::move(slide)});
    rebuild(own, std::move(objects.keep));
    finishControlStep(0, moved);
}

// The lighter node takes the slab: its box grows to `boundary` on `side`, its
// objects become the union of its own and the slab's, and it acknowledges.
void Node::takeSlab(int side, double boundary, std::vector<Shape> objects) {
    const Box own = withFace(region_->box(), params_.balance.axis, side, boundary);
    const size_t moved = objects.size();
    stats_.objectsReceived += moved;
    ++stats_.slidesTaken;
    outbox_.push_back({sideDir(side), Message::ack(boundary)});
    rebuild(own, uniteObjects(region_->objects(), std::move(objects)));
    finishControlStep(1, moved);
    balance_->tookSlab();
}

// What a sample ray passed on along the axis in a column beside costs the
// frame: a message's handling on both nodes, or, where the links are busy,
// its time on the axis link, as much of it as the node's busiest link is
// busy so far (the passes of a column go down the same few links one after
// another: on a full link the wire, not the processors, sets their pace;
// on an idle one they cost the processors alone). Its share of a batch.
// (The node's own links stand for the column beside's.) Measured: tetra-3
// on 8x8x8 at 100 MB/s, a move that passed rays down a full link made the
// frame 1.9 times the unbalanced one with the handling alone counted;
// Fig. 4's scene at 1 GB/s, along the axis at N = 5, f = 1, 1.07 with the
// whole wire counted, 0.89 with the handling alone (doc/balancing.md).
double Node::passCost() const {
    const int batch = std::max(1, params_.rayBatch);
    double busy = 0, wire = 0;
    for (int d = 0; d < kDirs; ++d)
        if (outLinks_[size_t(d)] && now_ > 0) busy = std::max(busy, double(outLinks_[size_t(d)]->occupied()) / double(now_));
    for (int side : {-1, +1})
        if (outLinks_[size_t(sideDir(side))]) {
            const LinkParams& l = linkTo(side);
            wire = std::max(wire, occupancy(l, wirePicos(l, kHeaderBytes + uint32_t(batch) * kRayBytes)));
        }
    return std::max(costs_.slabHandling(0), std::min(1.0, busy) * wire) / double(batch);
}

// ---- The guard's view of the links to the column neighbours ----

Picos Node::hopTime(int side) const {
    const LinkParams& l = linkTo(side);
    return l.latency + saturatedPicos(wirePicos(l, kHeaderBytes + kRayBytes));
}

// Only a report on a control lane is paced: it goes ahead of the rays, so
// without pacing reports could take the wire from them. On the rays' FIFO
// a report waits its turn behind them (0: no pacing).
Picos Node::reportTime(int side) const {
    const LinkParams& l = linkTo(side);
    if (l.controlDepth == 0) return 0;
    return saturatedPicos(wirePicos(l, kHeaderBytes + kLoadReportBytes));
}

Picos Node::linkOccupied(int side) const { return outLinks_[size_t(sideDir(side))]->occupied(); }

Picos Node::rayOccupies(int side) const {
    const LinkParams& l = linkTo(side);
    return saturatedPicos(occupancy(l, wirePicos(l, kHeaderBytes + kRayBytes)));
}

// What giving the slab would cost: both nodes handle a message and update
// their grids for its objects, and the slab crosses the link (latency and
// its bytes at the link's bandwidth).
Picos Node::slabCost(int side, double boundary) const {
    const SlabLoad load = slabLoad(region_->objects(), slabOf(region_->box(), params_.balance.axis, side, boundary), margin_);
    const LinkParams& l = linkTo(side);
    return saturatedPicos(costs_.slabHandling(load.objects) + double(l.latency) + wirePicos(l, load.bytes));
}

}  // namespace rt
