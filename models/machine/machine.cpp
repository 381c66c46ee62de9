#include "machine/machine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "balance/sample_split.h"

namespace rt {

const LinkStats LinkReport::kNoFigures{};

namespace {

int imageWidth(const Scene& s, const MachineConfig& c) { return c.width ? c.width : s.view.width; }
int imageHeight(const Scene& s, const MachineConfig& c) { return c.height ? c.height : s.view.height; }

}  // namespace

Machine::Machine(sc_core::sc_module_name name, const Scene& scene, const MachineConfig& config)
    : sc_module(name),
      scene_(scene),
      cfg_(config),
      width_(imageWidth(scene, config)),
      height_(imageHeight(scene, config)),
      world_(scene.worldBox()),
      columns_(config.balance.axis, config.dims),
      cuts_(Lattice::uniform(world_, config.dims)),
      camera_(scene.view, width_, height_),
      shader_(scene, config.maxDepth),
      units_("fb") {
    cfg_.validate();
    minThickness_ = minThicknessOf(cfg_, world_);
    // Each node's objects (and the median's columns) found by binning, not by
    // scanning the scene once per box.
    bins_ = std::make_unique<ObjectBins>(scene_.objects, cuts_, roundingMargin(world_));
    columnPlanes_ = initialPlanes(cfg_, cuts_, world_, *bins_, minThickness_, &camera_);
    const ColumnPlanes targets = startTargets();
    // Credit precision: the host's split, a node's split over its primary
    // rays, and one split per ray-tree level (a hit spawns at most L + 2 rays
    // and keeps a share: L + 3 parts).
    maxExp_ = ceilLog2(uint64_t(cfg_.nodeCount()) + 1) + ceilLog2(uint64_t(long(width_) * height_) + 1) +
              (cfg_.maxDepth + 1) * ceilLog2(scene.lights.size() + 3) + 2;
    buildUnits();
    buildNodes();
    buildLinks();
    for (Node& n : nodes_) n.setProgress(&watchdog_->progress());
    if (cfg_.faultDropFirstCredit) units_[0].dropFirstCredit();
    units_[0].onFinish([this] { endProcesses(); });
    if (!cfg_.vcdPath.empty()) setupTraces();
    giveOutPrimaryRays(targets);
}

Machine::~Machine() = default;

// With targets for the frame's start (resplit), each box at least the
// minimum thickness, exactly: the moves at the start reach a target only
// then (a give leaves its giver that thick), and a node generates its
// primary rays only once its faces are at their targets
// (Node::holdsPrimaries).
ColumnPlanes Machine::startTargets() const {
    if (cfg_.targetBoundaries.empty()) return columnPlanes_;
    return withInnerPlanes("target boundaries", columnPlanes_, cfg_.targetBoundaries, minThickness_, 0);
}

void Machine::buildUnits() {
    const int k = cfg_.fbUnits;
    const size_t pixels = size_t(long(width_) * height_);
    units_.init(size_t(k), [&](const char* n, size_t u) {
        auto* unit = new FrameBufferUnit(n, int(u), k, pixels, cfg_.hostCost, maxExp_, cfg_.showProgress, cfg_.quantum);
        keepProcess(*unit);
        return unit;
    });
}

// --faces ideal-layer: the faces every node of a layer shares, from the
// frame's starting planes.
void Machine::makeLayerFaces() {
    if (!cfg_.balance.idealLayerFaces) return;  // every column starts with the same planes (validate)
    const int ax = columns_.axis;
    const std::vector<double>& b = columnPlanes_.front();
    layerFaces_ = std::make_unique<IdealLayerFaces>(std::vector<double>(b.begin() + 1, b.end() - 1), world_.lo[ax],
                                                    world_.hi[ax], cfg_.balance.deadband, cfg_.balance.gainOf(),
                                                    minThickness_);
}

void Machine::buildNodes() {
    const int ax = columns_.axis;
    makeLayerFaces();
    nodeParams_ = std::make_unique<NodeParams>(shader_, camera_, cfg_.balance);
    NodeParams& p = *nodeParams_;
    p.world = world_;
    p.fbUnits = cfg_.fbUnits;
    p.fbBatch = cfg_.fbBatch;
    p.rayBatch = cfg_.rayBatch;
    p.spreadPrimaries = cfg_.spreadPrimaries;
    p.columnLength = cfg_.dims[ax];
    p.minThickness = minThickness_;
    p.quantum = cfg_.quantum;
    p.layerFaces = layerFaces_.get();
    p.runAhead = cfg_.lookaheadQuantum && !cfg_.balance.dynamic();
    nodes_.init(size_t(cfg_.nodeCount()), [&](size_t i) {
        const Cell c = cellAt(i, cfg_.dims);
        const Box b = nodeBox(c, cuts_, columns_, columnPlanes_);
        auto* node = new Node(nodeName(c).c_str(), c, b, bins_->overlapping(b), *nodeParams_, cfg_.processorCostsOf(c), cfg_.speedOf(c));
        keepProcess(*node);
        return node;
    });
    aimAtTargets();
}

// resplit: where each node's faces go at the frame's start.
void Machine::aimAtTargets() {
    if (cfg_.targetBoundaries.empty()) return;
    const int ax = columns_.axis;
    for (Node& node : nodes_) {
        const Cell& c = node.cell();
        const std::vector<double>& t = cfg_.targetBoundaries[size_t(columns_.columnOf(c))];
        const double nan = std::nan("");
        node.setStartTargets(c[ax] > 0 ? t[size_t(c[ax] - 1)] : nan, c[ax] + 1 < cfg_.dims[ax] ? t[size_t(c[ax])] : nan);
    }
}

// Links between face neighbours, one per direction, and the frame-buffer
// ports; each process's lookahead is the smallest of its inputs'. Then the
// watchdog, which the links mark progress to.
void Machine::buildLinks() {
    std::vector<Picos> nodeLookahead(nodes_.size(), kNoInput), unitLookahead(units_.size(), kNoInput);
    const size_t most = nodes_.size() * size_t(kDirs + cfg_.fbUnits);  // (grown once, not by doubling)
    links_.reserve(most);
    reportOf_.reserve(most);
    linkInfo_.reserve(nodes_.size() * size_t(kDirs + 1));
    meshLinks_.assign(nodes_.size() * kDirs, nullptr);
    for (Node& n : nodes_) {
        linkNeighbours(n, nodeLookahead);
        linkToFrameBuffer(n, unitLookahead);
    }
    linkUnits(unitLookahead);
    if (cfg_.balance.sampleCredit) linkColumnsToFrameBuffer(nodeLookahead);
    if (cfg_.lookaheadQuantum) setLookaheads(nodeLookahead, unitLookahead);
    buildExpress();
    if (cfg_.lookaheadQuantum && cfg_.fbLate > 0 && cfg_.vcdPath.empty() && cfg_.fbPort.outDepth == 0)
        for (int u = 1; u < cfg_.fbUnits; ++u) units_[size_t(u)].setLate(cfg_.fbLate);
    for (size_t i = 0; i < links_.size(); ++i) links_[i]->flowInto(&linkInfo_[reportOf_[i]].figures);  // (linkInfo_ grows no more)
    startWatchdog();
    for (auto* links : {&links_, &unitLinks_})
        for (auto& l : *links) {
            l->setProgress(&watchdog_->progress());
            l->keepDistributions(cfg_.linkDistributions);
            if (l->waitsForRoom()) roomLinks_.push_back(l.get());
        }
}

void Machine::linkNeighbours(Node& n, std::vector<Picos>& nodeLookahead) {
    const Cell c = n.cell();
    for (int d = 0; d < kDirs; ++d) {
        const Cell m = neighbour(c, d);
        if (!inMesh(m, cfg_.dims)) continue;
        const std::string lname = nodeName(c) + "_" + linkSuffix(d);
        // Without a dynamic policy there is no control traffic and the
        // lane stays empty: one FIFO is the same link, cheaper to simulate.
        LinkParams p = cfg_.meshLinkOf(c, d);
        if (!cfg_.balance.dynamic()) p.controlDepth = 0;
        // --sample-end credit: the sample's rays go on the control lane, which every link then has.
        if (cfg_.balance.sampleCredit && p.controlDepth == 0) p.controlDepth = p.depth;
        links_.push_back(std::make_unique<Link>(lname, p, smallestMeshMessage(cfg_.balance.dynamic())));
        n.bindOut(d, *links_.back());
        meshLinks_[nodeIndex(c) * kDirs + size_t(d)] = links_.back().get();
        nodes_[nodeIndex(m)].bindIn(opposite(d), *links_.back());
        Picos& receiver = nodeLookahead[nodeIndex(m)];
        receiver = std::min(receiver, links_.back()->lookahead());
        // A control lane places a control message among the data messages
        // on the wire when it is sent, from the slots the receiver has
        // returned by then, which come back one latency after it consumed:
        // its sender runs ahead by no more than that latency, as before
        // the smallest message's wire time counted (the lane is not yet
        // exact either way: doc/balancing.md, "The control lane").
        Picos& sender = nodeLookahead[nodeIndex(c)];
        if (p.controlDepth > 0) sender = std::min(sender, p.latency);
        reportOf_.push_back(linkInfo_.size());
        linkInfo_.emplace_back(lname, c, d, links_.back()->params(), 1);
    }
}

// A node's port to the frame buffer: a channel to each unit, reported as one.
void Machine::linkToFrameBuffer(Node& n, std::vector<Picos>& unitLookahead) {
    const int k = cfg_.fbUnits;
    const std::string fname = nodeName(n.cell()) + "_fb";
    const LinkParams port = cfg_.fbPortOf(n.cell());
    for (int u = 0; u < k; ++u) {
        links_.push_back(std::make_unique<Link>(k > 1 ? fname + std::to_string(u) : fname, port));
        n.bindFrameBuffer(*links_.back());           // the node's u-th binding
        units_[size_t(u)].addNodeLink(*links_.back());  // the unit's input from this node (nodes in order)
        unitLookahead[size_t(u)] = std::min(unitLookahead[size_t(u)], links_.back()->lookahead());
        reportOf_.push_back(linkInfo_.size());
    }
    linkInfo_.emplace_back(fname, n.cell(), -1, port, k);
}

// Unit 0 and each other unit: a port each way, for the end-of-frame check.
void Machine::linkUnits(std::vector<Picos>& unitLookahead) {
    for (int u = 1; u < cfg_.fbUnits; ++u) {
        const std::string up = "fb" + std::to_string(u) + "_to_fb0", down = "fb0_to_fb" + std::to_string(u);
        unitLinks_.push_back(std::make_unique<Link>(up, cfg_.fbPort));
        units_[size_t(u)].toController.bind(*unitLinks_.back());
        units_[0].in.bind(*unitLinks_.back());  // (after the nodes' links)
        unitLookahead[0] = std::min(unitLookahead[0], unitLinks_.back()->lookahead());
        unitLinks_.push_back(std::make_unique<Link>(down, cfg_.fbPort));
        units_[0].toUnits.bind(*unitLinks_.back());
        units_[size_t(u)].in.bind(*unitLinks_.back());
        unitLookahead[size_t(u)] = std::min(unitLookahead[size_t(u)], unitLinks_.back()->lookahead());
    }
}

// `sample` under --sample-end credit: unit 0's port to the lowest node of
// each column, bound to the node's port below it (it has no neighbour
// there), for the word that the sample is done; with a control lane, which
// the node takes ahead of rays.
void Machine::linkColumnsToFrameBuffer(std::vector<Picos>& nodeLookahead) {
    const int ax = columns_.axis;
    std::vector<Link*> byColumn(size_t(columns_.count()), nullptr);
    for (size_t i = 0; i < nodes_.size(); ++i) {
        Node& n = nodes_[i];
        if (n.cell()[ax] != 0) continue;
        LinkParams p = cfg_.fbPortOf(n.cell());
        p.controlDepth = std::max(p.controlDepth, 1);
        unitLinks_.push_back(std::make_unique<Link>("fb0_to_" + nodeName(n.cell()), p));
        n.bindIn(dirOf(ax, -1), *unitLinks_.back());
        byColumn[size_t(columns_.columnOf(n.cell()))] = unitLinks_.back().get();
        nodeLookahead[i] = std::min(nodeLookahead[i], unitLinks_.back()->lookahead());
    }
    for (Link* l : byColumn) units_[0].addColumnLink(*l);
}

// --quantum lookahead: each process runs ahead of the kernel by its own
// lookahead, the soonest a message not yet sent can reach it (every sender's
// time is at least the kernel's): the smallest over its input links of
// their latency plus the smallest message's time on their wire. A node's
// inputs are its neighbours' links (rays of 132 bytes, 16 with a dynamic
// policy's acks; a node that sends on a control lane, no more than the
// lane's latency, above); a unit's, the nodes' ports and the units' links
// (a header of 8 bytes). A process with no inputs (one node) takes the
// machine's smallest.
void Machine::setLookaheads(const std::vector<Picos>& nodes, const std::vector<Picos>& units) {
    const Picos fallback = cfg_.lookahead();
    for (size_t i = 0; i < nodes_.size(); ++i) nodes_[i].setQuantum(nodes[i] == kNoInput ? fallback : nodes[i]);
    for (size_t u = 0; u < units_.size(); ++u) units_[u].setQuantum(units[u] == kNoInput ? fallback : units[u]);
}

void Machine::startWatchdog() {
    Watchdog::Machine watched{[this] { return controller().done(); },
                              [this] {
                                  if (vcd_) vcd_->flush(traceHorizon());
                              },
                              [this] { return whoHolds(); }, [this] { endProcesses(); }};
    watchdog_ = std::make_unique<Watchdog>("watchdog", cfg_.watchdogSpanOrDefault(scene_.objects.size()),
                                           cfg_.watchdogWall, std::move(watched));
    keepProcess(*watchdog_);
}

// The host's job description (initial_split.h): each node's primary rays
// and credit, and the background of the rays that miss the world.
void Machine::giveOutPrimaryRays(const ColumnPlanes& planes) {
    // With targets for the frame's start (resplit), each node generates the
    // primary rays of the box it is to have, once it has it (Node::takeWork).
    PrimaryRays primaries = assignPrimaryRays(camera_, world_, cuts_, columns_, planes, cfg_.pixelStride);
    Counters hostCounters;
    for (const RayJob& j : primaries.misses)
        units_[j.pixel % uint32_t(cfg_.fbUnits)].addOwn(shader_.miss(j, hostCounters));
    primaryMisses_ = primaries.misses.size();
    const bool sample = cfg_.balance.policy == "sample" && cfg_.targetBoundaries.empty();
    const std::vector<bool> gathers = sample ? prepareSample(primaries.perNode, planes) : std::vector<bool>{};
    CreditShares credit = shareCredit(primaries.perNode, maxExp_);
    if (sample && cfg_.balance.sampleCredit) expectSampleCredit(primaries.perNode, credit, gathers);
    useExpress(primaries.perNode);
    for (size_t i = 0; i < nodes_.size(); ++i)
        nodes_[i].assignPrimaries(std::move(primaries.perNode[i]), credit.exp[i], credit.remainder[i]);
    units_[0].keep(credit.host);
}

// `sample`'s first frame (sample_split.h): which columns gather their
// sample, and the columns beside each. Under --sample-end credit every
// column gathers: the frame buffer's word comes once all the sample's rays
// have ended, so each column's own sample is whole, whether or not it
// generates primary rays. Once generated, a column none of whose nodes
// generates primary rays (across the axis, all but the front row) has seen
// none of its sample yet, and holds its faces: the planes of the column in
// front of it, which it used to take, did not fit its work, and the rays
// they passed on against the columns beside it cost more than the move
// gained (doc/balancing.md, "Columns that generate no primary rays").
// Every column counts the passes its
// planes would cause against those beside it, the ones that hold and the
// ones that move (their top nodes tell each other their planes).
std::vector<bool> Machine::prepareSample(const std::vector<std::vector<uint32_t>>& perNode, const ColumnPlanes& planes) {
    const ColumnGeometry& g = columns_;
    std::vector<bool> gathers(size_t(g.count()), cfg_.balance.sampleCredit);
    for (size_t i = 0; i < nodes_.size(); ++i)
        if (!perNode[i].empty()) gathers[size_t(g.columnOf(nodes_[i].cell()))] = true;
    // The columns beside are the same for every node of a column, so its
    // nodes agree whether the sum carries the sides; a column too long for
    // them in the sum counts none (sidesFit).
    const bool sidesRoom = sidesFit(g.length());
    for (Node& n : nodes_) {
        const size_t col = size_t(g.columnOf(n.cell()));
        std::vector<int> beside;
        for (int d = 0; d < kDirs; ++d)
            if (sidesRoom && dirAxis(d) != g.axis && inMesh(neighbour(n.cell(), d), cfg_.dims)) beside.push_back(d);
        std::vector<double> faces;  // (the top node's: what it proposes if the column holds)
        if (n.cell()[g.axis] == g.length() - 1) faces.assign(planes[col].begin() + 1, planes[col].end() - 1);
        n.setSample(gathers[col], std::move(beside), std::move(faces));
    }
    return gathers;
}

// --sample-end credit: unit 0 learns the credit the sample's primary rays
// carry (each node's sample pixels at its exponent) and which columns to
// tell when it is back.
void Machine::expectSampleCredit(const std::vector<std::vector<uint32_t>>& perNode, const CreditShares& credit,
                                 const std::vector<bool>& gathers) {
    Credit total(maxExp_);
    const uint32_t width = uint32_t(camera_.width());
    for (size_t i = 0; i < perNode.size(); ++i) {
        uint64_t n = 0;
        for (uint32_t p : perNode[i]) n += inSample(p, width) ? 1 : 0;
        total.add(credit.exp[i], n);
    }
    units_[0].expectSample(total, gathers);
}

void Machine::endFrame() {
    if (express_) express_->countOnLinks();
    for (Node& n : nodes_) n.endFrame(frameEnd(), !stopped());
    for (auto& l : links_) l->endFrame(frameEnd());
}

// Which nodes still hold work or credit, and how much credit unit 0 lacks:
// where to look when a frame does not end.
std::string Machine::whoHolds() const {
    std::ostringstream s;
    int listed = 0, more = 0;
    for (const Node& n : nodes_) {
        const std::string h = n.holding();
        if (h.empty()) continue;
        if (listed < 6) s << (listed ? "; " : "") << nodeName(n.cell()) << ": " << h;
        else ++more;
        ++listed;
    }
    if (!listed) s << "no node holds work or credit";
    if (more) s << "; and " << more << " more nodes";
    s << "; unit 0 has " << controller().creditReturned() << " of the frame's credit back";
    return s.str();
}

MachineResult Machine::collect(double wallSeconds, bool last) {
    MachineResult r;
    r.links = last ? std::move(linkInfo_) : linkInfo_;
    // The links' flows are in their entries already (Link::flowInto); their
    // counts by type are added. The last frame's links are emptied as they
    // are read: their lanes and rings make room for the rest of the report.
    for (size_t i = 0; i < links_.size(); ++i) {
        if (links_[i]->hasCarried()) links_[i]->addCountsTo(r.links[reportOf_[i]].fill());
        if (last) links_[i]->restart();
    }
    r.image = assembleImage(units_, width_, height_);
    for (const FrameBufferUnit& u : units_) r.frameBuffer.push_back({u.stats()});
    r.renderTime = frameEnd();
    r.frameStart = frameOrigin;
    r.incomplete = watchdog_->stall();
    r.nodes.reserve(nodes_.size());  // (grown by doubling, a copy of 32,768 nodes' figures stood beside the last)
    for (const Node& n : nodes_) {
        r.nodes.push_back(n.stats());
        r.cells.push_back(n.cell());
        r.boxes.push_back(n.region().box());
        r.objectsPerNode.push_back(n.region().objects().size());
        uint64_t bytes = 0;
        for (const Shape& s : n.region().objects()) bytes += objectBytes(s);
        r.objectBytesPerNode.push_back(bytes);
        const Lattice* g = n.region().accelerator().grid();
        if (g && !n.region().objects().empty())
            r.grids.push_back(MachineResult::Grid{{g->cells(0), g->cells(1), g->cells(2)}, g->bounds()});
        else
            r.grids.push_back(std::nullopt);
    }
    r.boundaries = boundaryHistories();
    r.worldBox = world_;
    r.primaryMisses = primaryMisses_;
    r.express = cfg_.usesRelay();
    r.deltaCycles = sc_core::sc_delta_count() - deltaAtStart_;
    r.wallSeconds = wallSeconds;
    r.gtkw = gtkw_;
    return r;
}

// Each boundary's positions over time, from the slides its two nodes gave.
std::vector<BoundaryHistory> Machine::boundaryHistories() const {
    const ColumnGeometry& g = columns_;
    std::vector<BoundaryHistory> out;
    for (int j = 0; j < g.dims[g.v]; ++j)
        for (int i = 0; i < g.dims[g.u]; ++i)
            for (int k = 1; k < g.length(); ++k) {
                BoundaryHistory h{{i, j}, k, {{0, columnPlanes_[size_t(g.indexOf(i, j))][size_t(k)]}}};
                std::vector<std::pair<Picos, double>> moves;
                for (const SlideEvent& e : nodes_[nodeIndex(g.cell(i, j, k - 1))].stats().slides)
                    if (e.side > 0) moves.push_back({e.t, e.boundary});
                for (const SlideEvent& e : nodes_[nodeIndex(g.cell(i, j, k))].stats().slides)
                    if (e.side < 0) moves.push_back({e.t, e.boundary});
                std::stable_sort(moves.begin(), moves.end(),
                                 [](const auto& a, const auto& b) { return a.first < b.first; });
                h.positions.insert(h.positions.end(), moves.begin(), moves.end());
                out.push_back(std::move(h));
            }
    return out;
}

void Machine::start_of_simulation() { started_ = std::chrono::steady_clock::now(); }

}  // namespace rt
