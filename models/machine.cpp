#include "machine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "trace_writer.h"

namespace rt {

volatile std::sig_atomic_t stopSignal = 0;

namespace {

int imageWidth(const Scene& s, const MachineConfig& c) { return c.width ? c.width : s.view.width; }
int imageHeight(const Scene& s, const MachineConfig& c) { return c.height ? c.height : s.view.height; }

// A link's name after its node's: "px", "mz", ...
std::string linkSuffix(int d) { return std::string(d % 2 ? "m" : "p") + "xyz"[dirAxis(d)]; }

std::string cellName(const Cell& c) {
    std::ostringstream s;
    s << "node_" << c[0] << "_" << c[1] << "_" << c[2];
    return s.str();
}

}  // namespace

Machine::Machine(sc_core::sc_module_name name, const Scene& scene, const MachineConfig& config)
    : sc_module(name),
      scene_(scene),
      cfg_(config),
      width_(imageWidth(scene, config)),
      height_(imageHeight(scene, config)),
      world_(scene.worldBox()),
      cuts_(Lattice::uniform(world_, config.dims)),
      camera_(scene.view, width_, height_),
      shader_(scene, config.maxDepth),
      units_("fb"),
      nodes_("node") {
    cfg_.validate();
    const int ax = cfg_.balance.axis;
    minThickness_ = cfg_.balance.minThickness * world_.extent()[ax] / cfg_.dims[ax];
    // Each node's objects (and the median's columns) found by binning, not by
    // scanning the scene once per box.
    const ObjectBins bins(scene_.objects, cuts_, roundingMargin(world_));
    columnBounds_ = initialBoundaries(bins);
    if (!cfg_.targetBoundaries.empty() && cfg_.targetBoundaries.size() != columnBounds_.size())
        throw std::invalid_argument("target boundaries: " + std::to_string(cfg_.targetBoundaries.size()) +
                                    " columns, the mesh has " + std::to_string(columnBounds_.size()));
    // Credit precision: the host's split, a node's split over its primary
    // rays, and one split per ray-tree level (a hit spawns at most L + 2 rays
    // and keeps a share: L + 3 parts).
    const long pixels = long(width_) * height_;
    const int k = cfg_.fbUnits;
    maxExp_ = ceilLog2(uint64_t(cfg_.nodeCount()) + 1) + ceilLog2(uint64_t(pixels) + 1) +
              (cfg_.maxDepth + 1) * ceilLog2(scene.lights.size() + 3) + 2;
    units_.init(size_t(k), [&](const char* n, size_t u) {
        return new FrameBufferUnit(n, int(u), k, size_t(pixels), cfg_.hostCost, maxExp_,
                                   cfg_.showProgress, cfg_.quantum);
    });

    if (cfg_.balance.idealLayerFaces) {  // every column starts with the same planes (validate)
        const std::vector<double>& b = columnBounds_.front();
        layerFaces_ = std::make_unique<IdealLayerFaces>(std::vector<double>(b.begin() + 1, b.end() - 1), world_.lo[ax],
                                                        world_.hi[ax], cfg_.balance.deadband, cfg_.balance.gainOf(),
                                                        minThickness_);
    }
    nodeParams_.reset(new NodeParams{shader_,       camera_,      world_,        k,
                                     cfg_.fbBatch,  cfg_.rayBatch, cfg_.balance,  cfg_.dims[ax],
                                     minThickness_, cfg_.quantum,  layerFaces_.get(),
                                     cfg_.lookaheadQuantum && !cfg_.balance.dynamic()});
    const NodeParams& params = *nodeParams_;
    nodes_.init(size_t(cfg_.nodeCount()), [&](const char*, size_t i) {
        const Cell c{int(i % cfg_.dims[0]), int(i / cfg_.dims[0] % cfg_.dims[1]), int(i / cfg_.dims[0] / cfg_.dims[1])};
        Box b = cuts_.cellBox(c);
        b.lo[ax] = columnBounds_[columnOf(c)][c[ax]];
        b.hi[ax] = columnBounds_[columnOf(c)][c[ax] + 1];
        return new Node(cellName(c).c_str(), c, b, bins.overlapping(b), params,
                        cfg_.costsOf(c), cfg_.speedOf(c));
    });
    if (!cfg_.targetBoundaries.empty())  // resplit: where each node's faces go at the frame's start
        for (Node& node : nodes_) {
            const Cell& c = node.cell();
            const std::vector<double>& t = cfg_.targetBoundaries[size_t(columnOf(c))];
            if (t.size() != size_t(cfg_.dims[ax] - 1)) throw std::invalid_argument("target boundaries: a column of the wrong size");
            const double nan = std::nan("");
            node.setStartTargets(c[ax] > 0 ? t[size_t(c[ax] - 1)] : nan, c[ax] + 1 < cfg_.dims[ax] ? t[size_t(c[ax])] : nan);
        }

    // Links between face neighbours, one per direction, and the frame-buffer
    // ports; each process's lookahead is the smallest of its inputs'.
    std::vector<Picos> nodeLookahead(nodes_.size(), kNoInput), unitLookahead(units_.size(), kNoInput);
    auto lowerTo = [](Picos& l, Picos input) { l = std::min(l, input); };
    for (Node& n : nodes_) {
        const Cell c = n.cell();
        for (int d = 0; d < kDirs; ++d) {
            Cell m = c;
            m[dirAxis(d)] += dirStep(d);
            if (m[dirAxis(d)] < 0 || m[dirAxis(d)] >= cfg_.dims[dirAxis(d)]) continue;
            const std::string lname = cellName(c) + "_" + linkSuffix(d);
            // Without a dynamic policy there is no control traffic and the
            // lane stays empty: one FIFO is the same link, cheaper to simulate.
            LinkParams p = cfg_.linkOf(c, d);
            if (!cfg_.balance.dynamic()) p.controlDepth = 0;
            links_.push_back(std::make_unique<Link>(lname, p, smallestMeshMessage(cfg_.balance.dynamic())));
            n.out[d].bind(*links_.back());
            meshLinks_[{nodeIndex(c), d}] = links_.back().get();
            nodes_[nodeIndex(m)].in[opposite(d)].bind(*links_.back());
            lowerTo(nodeLookahead[size_t(nodeIndex(m))], links_.back()->lookahead());
            // A control lane places a control message among the data messages
            // on the wire when it is sent, from the slots the receiver has
            // returned by then, which come back one latency after it consumed:
            // its sender runs ahead by no more than that latency, as before
            // the smallest message's wire time counted (the lane is not yet
            // exact either way: doc/balancing.md, "The control lane").
            if (p.controlDepth > 0) lowerTo(nodeLookahead[size_t(nodeIndex(c))], p.latency);
            reportOf_.push_back(linkInfo_.size());
            linkInfo_.push_back({lname, c, d, links_.back()->params(), 1, {}});
        }
        // Its port to the frame buffer: a channel to each unit, reported as one.
        const std::string fname = cellName(c) + "_fb";
        for (int u = 0; u < k; ++u) {
            links_.push_back(std::make_unique<Link>(k > 1 ? fname + std::to_string(u) : fname, cfg_.fbPort));
            n.fb.bind(*links_.back());                   // the node's u-th binding
            units_[size_t(u)].in.bind(*links_.back());   // the unit's binding for this node (nodes in order)
            lowerTo(unitLookahead[size_t(u)], links_.back()->lookahead());
            reportOf_.push_back(linkInfo_.size());
        }
        linkInfo_.push_back({fname, c, -1, cfg_.fbPort, k, {}});
    }
    // Unit 0 and each other unit: a port each way, for the end-of-frame check.
    for (int u = 1; u < k; ++u) {
        const std::string up = "fb" + std::to_string(u) + "_to_fb0", down = "fb0_to_fb" + std::to_string(u);
        unitLinks_.push_back(std::make_unique<Link>(up, cfg_.fbPort));
        units_[size_t(u)].toController.bind(*unitLinks_.back());
        units_[0].in.bind(*unitLinks_.back());  // after the nodes' ports
        lowerTo(unitLookahead[0], unitLinks_.back()->lookahead());
        unitLinks_.push_back(std::make_unique<Link>(down, cfg_.fbPort));
        units_[0].toUnits.bind(*unitLinks_.back());
        units_[size_t(u)].in.bind(*unitLinks_.back());
        lowerTo(unitLookahead[size_t(u)], unitLinks_.back()->lookahead());
    }
    if (cfg_.lookaheadQuantum) setLookaheads(nodeLookahead, unitLookahead);
    if (cfg_.lookaheadQuantum && cfg_.fbLate > 0 && cfg_.vcdPath.empty() && cfg_.fbPort.outDepth == 0)
        for (int u = 1; u < k; ++u) units_[size_t(u)].setLate(cfg_.fbLate);
    for (auto* links : {&links_, &unitLinks_})
        for (auto& l : *links) {
            l->setProgress(&progress_);
            l->keepDistributions(cfg_.linkDistributions);
        }
    for (Node& n : nodes_) n.setProgress(&progress_);
    if (cfg_.faultDropFirstCredit) units_[0].dropFirstCredit();
    units_[0].onFinish([this] { endProcesses(); });
    SC_METHOD(watch);
    if (!cfg_.vcdPath.empty()) setupTraces();
    assignPrimaryRays();
}

Machine::~Machine() = default;

// --quantum lookahead: each process runs ahead of the kernel by its own
// lookahead, the soonest a message not yet sent can reach it (every sender's
// time is at least the kernel's): the smallest over its input links of
// their latency plus the smallest message's time on their wire. A node's
// inputs are its neighbours' links (rays of 132 bytes, 16 with a dynamic
// policy's acks: 232 or 116 ns at rtsim's 100 ns and 1 GB/s, against the
// latency's 100 ns alone; a node that sends on a control lane, no more than
// the lane's latency, below); a unit's, the nodes' ports and the units'
// links (a header of 8 bytes). A process with no inputs (one node) takes the
// machine's smallest.
void Machine::setLookaheads(const std::vector<Picos>& nodes, const std::vector<Picos>& units) {
    const Picos fallback = cfg_.lookahead();
    for (size_t i = 0; i < nodes_.size(); ++i) nodes_[i].setQuantum(nodes[i] == kNoInput ? fallback : nodes[i]);
    for (size_t u = 0; u < units_.size(); ++u) units_[u].setQuantum(units[u] == kNoInput ? fallback : units[u]);
}

// The watchdog: wakes every span of simulated time, or every millisecond
// (or a thousandth of the span, if longer) if that is sooner, so at most a
// few times in most frames and often enough to see the wall clock; and
// stops a run in which nothing moved for a whole span, or that has run past
// the wall-clock limit. Stopping it: a
// stuck run with balancing never ends by itself (the nodes keep waking for
// their intervals), and without balancing it ends only with the kernel out
// of events.
void Machine::watch() {
    const auto wake = [&] { sc_core::next_trigger(sc_core::sc_time::from_value(watchPeriod_)); };
    if (watchPeriod_ == 0) {  // its first activation, at time 0
        watchSpan_ = cfg_.watchdogSpanOrDefault(scene_.objects.size());
        watchPeriod_ = std::min<Picos>(watchSpan_, std::max<Picos>(1000000000, watchSpan_ / 1000));
        watchStart_ = std::chrono::steady_clock::now();
        wake();
        return;
    }
    if (controller().done()) return;
    if (vcd_) vcd_->flush(traceHorizon());  // the waveform so far, on disk
    const Picos now = sc_core::sc_time_stamp().value();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - watchStart_).count();
    std::ostringstream why;
    if (stopSignal) {
        why << "interrupted by signal " << int(stopSignal) << " at " << formatTime(now) << " of simulated time";
    } else if (now >= progress_.last + watchSpan_) {
        why << "no ray, contribution or credit moved for " << formatTime(now - progress_.last)
            << " of simulated time (since " << formatTime(progress_.last) << ")";
    } else if (cfg_.watchdogWall > 0 && wall > cfg_.watchdogWall) {
        why << "the wall-clock limit of " << cfg_.watchdogWall << " s was reached at " << formatTime(now)
            << " of simulated time";
    } else {
        wake();
        return;
    }
    stalledAt_ = now;
    stall_ = why.str() + "; " + whoHolds();
    endProcesses();
    sc_core::sc_stop();
}

// Ends every process but the caller's, from within the simulation, just
// before it stops: sc_stop finishes the current delta cycle, and a process
// ended here does not run in it. (When the nodes were threads this also
// unwound their stacks, which LeakSanitizer otherwise found lost; the
// processes are all method processes now and hold nothing on a stack.)
void Machine::endProcesses() {
    const sc_core::sc_process_handle self = sc_core::sc_get_current_process_handle();
    auto end = [&](const sc_core::sc_object& module) {
        for (sc_core::sc_object* child : module.get_child_objects()) {
            sc_core::sc_process_handle h(child);
            if (h.valid() && h != self && !h.terminated()) h.kill();
        }
    };
    for (const Node& n : nodes_) end(n);
    for (const FrameBufferUnit& u : units_) end(u);
    end(*this);  // the watchdog
}

// Which nodes still hold work or credit, and how much credit unit 0 lacks:
// where to look when a frame does not end.
std::string Machine::whoHolds() const {
    std::ostringstream s;
    int listed = 0, more = 0;
    for (const Node& n : nodes_) {
        const std::string h = n.holding();
        if (h.empty()) continue;
        if (listed < 6) s << (listed ? "; " : "") << cellName(n.cell()) << ": " << h;
        else ++more;
        ++listed;
    }
    if (!listed) s << "no node holds work or credit";
    if (more) s << "; and " << more << " more nodes";
    s << "; unit 0 has " << controller().creditReturned() << " of the frame's credit back";
    return s.str();
}

int Machine::columnOf(const Cell& c) const {
    const int ax = cfg_.balance.axis, u = (ax + 1) % 3, v = (ax + 2) % 3;
    return c[u] + cfg_.dims[u] * c[v];
}

std::vector<std::vector<double>> Machine::initialBoundaries(const ObjectBins& bins) const {
    const int ax = cfg_.balance.axis, u = (ax + 1) % 3, v = (ax + 2) % 3, n = cfg_.dims[ax];
    std::vector<std::vector<double>> bounds(size_t(cfg_.dims[u] * cfg_.dims[v]), cuts_.planes(ax));
    if (!cfg_.startBoundaries.empty()) {  // where a previous frame left them
        if (cfg_.startBoundaries.size() != bounds.size())
            throw std::invalid_argument("start boundaries: " + std::to_string(cfg_.startBoundaries.size()) +
                                        " columns, the mesh has " + std::to_string(bounds.size()));
        for (size_t c = 0; c < bounds.size(); ++c) {
            const std::vector<double>& inner = cfg_.startBoundaries[c];
            if (inner.size() != size_t(n - 1))
                throw std::invalid_argument("start boundaries: column " + std::to_string(c) + " has " +
                                            std::to_string(inner.size()) + " planes, not " + std::to_string(n - 1));
            for (int k = 1; k < n; ++k) bounds[c][size_t(k)] = inner[size_t(k - 1)];
            for (int k = 0; k < n; ++k)  // the guard's minimum thickness, with the rounding of a report's decimals
                if (!(bounds[c][size_t(k + 1)] - bounds[c][size_t(k)] >= minThickness_ * (1 - 1e-9)))
                    throw std::invalid_argument("start boundaries: column " + std::to_string(c) + ", box " +
                                                std::to_string(k) + " is thinner than the minimum thickness");
        }
        return bounds;
    }
    if (cfg_.balance.policy != "median") return bounds;
    for (int j = 0; j < cfg_.dims[v]; ++j)
        for (int i = 0; i < cfg_.dims[u]; ++i) {
            Cell c{};
            c[u] = i;
            c[v] = j;
            c[ax] = 0;
            Box column = cuts_.cellBox(c);
            column.lo[ax] = world_.lo[ax];
            column.hi[ax] = world_.hi[ax];
            std::vector<double> centres;
            for (const Shape& s : bins.overlapping(column)) {
                const Box ob = s.bounds();
                centres.push_back(0.5 * (ob.lo[ax] + ob.hi[ax]));
            }
            std::vector<double>& b = bounds[size_t(columnOf(c))];
            if (centres.empty()) continue;
            std::sort(centres.begin(), centres.end());
            // Boundary k at the k/N quantile of the object centres, kept inside
            // the guards: every box at least the minimum thickness.
            for (int k = 1; k < n; ++k) {
                const double q = centres[std::min(centres.size() - 1, centres.size() * size_t(k) / size_t(n))];
                const double lo = b[size_t(k - 1)] + minThickness_, hi = world_.hi[ax] - (n - k) * minThickness_;
                b[size_t(k)] = std::clamp(q, lo, hi);
            }
        }
    return bounds;
}

// The host's job description: each primary ray goes to the node that owns
// the point where it starts inside the world box; rays that miss the world
// are the background, which the host fills in itself. Credit: the host keeps
// what it does not hand out; each node gets 2^-hostExp and gives each of its
// P primary rays 2^-(hostExp + ceil(log2 P)), keeping the rest.
void Machine::assignPrimaryRays() {
    std::vector<std::vector<uint32_t>> perNode(nodes_.size());
    Counters hostCounters;
    const int ax = cfg_.balance.axis;
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            const RayJob j = primaryJob(camera_, x, y, world_);
            std::optional<Cell> c = cuts_.locate(j.ray, j.t0);
            if (c) {  // along the axis, the column's own boundaries decide
                const std::vector<double>& b = columnBounds_[columnOf(*c)];
                for (int k = 0; k < cfg_.dims[ax]; ++k) {
                    const Interval s = slabInterval(j.ray, ax, b[k], b[k + 1]);
                    if (s.lo <= j.t0 && j.t0 < s.hi) (*c)[ax] = k;
                }
            }
            if (c) {
                perNode[nodeIndex(*c)].push_back(j.pixel);
            } else {
                units_[j.pixel % uint32_t(cfg_.fbUnits)].addOwn(shader_.miss(j, hostCounters));
                ++primaryMisses_;
            }
        }
    size_t busyNodes = 0;
    for (const auto& p : perNode) busyNodes += !p.empty();
    const int hostExp = ceilLog2(busyNodes);
    Credit kept = Credit::one(maxExp_);
    for (size_t i = 0; i < nodes_.size(); ++i) {
        Credit remainder(maxExp_);
        int exp = 0;
        if (!perNode[i].empty()) {
            const uint64_t p = perNode[i].size();
            const int c = ceilLog2(p);
            exp = hostExp + c;
            remainder.add(exp, (uint64_t(1) << c) - p);
        }
        nodes_[i].assignPrimaries(std::move(perNode[i]), exp, remainder);
    }
    // 1 - busyNodes * 2^-hostExp stays with the host (unit 0).
    Credit rest(maxExp_);
    rest.add(hostExp, (uint64_t(1) << hostExp) - busyNodes);
    units_[0].keep(rest);
}

void Machine::checkConservation() const {
    if (!stall_.empty()) return;  // an incomplete run: nothing to conserve yet
    uint64_t created = primaryMisses_, terminated = primaryMisses_, sent = primaryMisses_;
    for (const Node& n : nodes_) {
        created += n.stats().raysCreated;
        terminated += n.stats().raysTerminated;
        sent += n.stats().contributionsSent;
    }
    if (!controller().done()) throw std::runtime_error("conservation: the frame never completed");
    if (created != terminated) {
        std::ostringstream s;
        s << "conservation: " << created << " rays created but " << terminated << " terminated";
        throw std::runtime_error(s.str());
    }
    uint64_t received = primaryMisses_;
    for (const FrameBufferUnit& u : units_) received += u.stats().contributions;
    if (sent != received) {
        std::ostringstream s;
        s << "conservation: " << sent << " contributions sent but " << received << " received";
        throw std::runtime_error(s.str());
    }
    // Time accounting: every node was busy or waiting until the frame was done.
    const Picos end = controller().renderTime();
    for (const Node& n : nodes_) {
        const NodeStats& s = n.stats();
        if (s.lastActive > end || s.busy + s.wait != end)
            throw std::runtime_error(std::string("time accounting: busy + wait != render time at ") + n.name() +
                                     " (busy " + std::to_string(s.busy) + ", wait " + std::to_string(s.wait) +
                                     ", last active " + std::to_string(s.lastActive) + ", end " + std::to_string(end) + " ps)");
    }
    // Rays and frame-buffer traffic must all be delivered; balancing messages
    // (load reports, slides, acks) may still be on their way when the frame ends.
    for (const auto* links : {&links_, &unitLinks_})
        for (const auto& l : *links)
            for (MsgType t : {MsgType::Ray, MsgType::Contributions, MsgType::Credit, MsgType::FbExpect, MsgType::FbDone})
                if (l->inFlight(t))
                    throw std::runtime_error(std::string("conservation: ") + msgTypeName(t) + " messages left on " +
                                             l->name());
    // Ownership: along the axis, neighbours' faces meet, except where a slab is
    // being handed over (a slide still on the link between them).
    const int ax = cfg_.balance.axis;
    for (const Node& n : nodes_) {
        const Box& b = n.region().box();
        if (!(b.hi[ax] - b.lo[ax] >= minThickness_ * (1 - 1e-9)))
            throw std::runtime_error(std::string("guard: box thinner than the minimum at ") + n.name());
        Cell up = n.cell();
        ++up[ax];
        if (up[ax] >= cfg_.dims[ax] || nodes_[nodeIndex(up)].region().box().lo[ax] == b.hi[ax]) continue;
        const Link* l1 = meshLinks_.at({nodeIndex(n.cell()), dirOf(ax, +1)});
        const Link* l2 = meshLinks_.at({nodeIndex(up), dirOf(ax, -1)});
        if (!l1->inFlight(MsgType::Slide) && !l2->inFlight(MsgType::Slide))
            throw std::runtime_error(std::string("ownership: a gap or overlap above ") + n.name());
    }
}

MachineResult Machine::collect(double wallSeconds) {
    MachineResult r;
    r.image = assembleImage(units_, width_, height_);
    for (const FrameBufferUnit& u : units_) r.frameBuffer.push_back({u.stats()});
    r.renderTime = frameEnd();
    r.incomplete = stall_;
    for (const Node& n : nodes_) {
        r.nodes.push_back(n.stats());
        r.cells.push_back(n.cell());
        r.boxes.push_back(n.region().box());
        r.objectsPerNode.push_back(n.region().objects().size());
    }
    r.links = linkInfo_;
    for (size_t i = 0; i < links_.size(); ++i) mergeChannel(r.links[reportOf_[i]].stats, links_[i]->stats());
    r.boundaries = boundaryHistories();
    r.worldBox = world_;
    r.primaryMisses = primaryMisses_;
    r.deltaCycles = sc_core::sc_delta_count();
    r.wallSeconds = wallSeconds;
    return r;
}

// Each boundary's positions over time, from the slides its two nodes gave.
std::vector<BoundaryHistory> Machine::boundaryHistories() const {
    const int ax = cfg_.balance.axis, u = (ax + 1) % 3, v = (ax + 2) % 3, n = cfg_.dims[ax];
    std::vector<BoundaryHistory> out;
    for (int j = 0; j < cfg_.dims[v]; ++j)
        for (int i = 0; i < cfg_.dims[u]; ++i)
            for (int k = 1; k < n; ++k) {
                Cell below{}, above{};
                below[u] = above[u] = i;
                below[v] = above[v] = j;
                below[ax] = k - 1;
                above[ax] = k;
                BoundaryHistory h{{i, j}, k, {{0, columnBounds_[columnOf(below)][k]}}};
                std::vector<std::pair<Picos, double>> moves;
                for (const SlideEvent& e : nodes_[nodeIndex(below)].stats().slides)
                    if (e.side > 0) moves.push_back({e.t, e.boundary});
                for (const SlideEvent& e : nodes_[nodeIndex(above)].stats().slides)
                    if (e.side < 0) moves.push_back({e.t, e.boundary});
                std::stable_sort(moves.begin(), moves.end(),
                                 [](const auto& a, const auto& b) { return a.first < b.first; });
                h.positions.insert(h.positions.end(), moves.begin(), moves.end());
                out.push_back(std::move(h));
            }
    return out;
}

// The VCD's signals: per traced node (all, unless --trace-nodes) busy,
// wait, queue and load, and under it its traced links (its own, and those
// --trace-links names); the frame-buffer units; every boundary when
// balancing. The header is written now, the changes as the run goes.
void Machine::setupTraces() {
    using K = VcdStream::Kind;
    vcd_ = std::make_unique<VcdStream>();
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
    std::vector<NodeTrace> traces(nodes_.size());
    std::vector<LinkTrace> fbTraces(nodes_.size());  // each traced frame-buffer port's signals
    for (size_t i = 0; i < nodes_.size(); ++i) {
        const std::string name = cellName(nodes_[i].cell());
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
            if (!fb && !meshLinks_.count({i, d})) continue;  // a mesh face
            const std::string scope = name + "." + (fb ? std::string("fb") : linkSuffix(d));
            LinkTrace lt{&v, v.declare(scope, "wire", fb ? K::Integer : K::Bit), v.declare(scope, "buffered", K::Integer),
                         v.declare(scope, "backlog", K::Integer)};
            if (fb) {
                fbTraces[i] = lt;  // (its channels below)
            } else {
                Link* l = meshLinks_.at({i, d});
                l->setTrace(lt);
                tracedLinks_.push_back(l);
            }
        }
    }
    for (size_t j = 0; j < links_.size(); ++j) {  // a traced port's channels, one per unit, share its signals
        const LinkReport& info = linkInfo_[reportOf_[j]];
        if (info.dir >= 0) continue;
        const LinkTrace& lt = fbTraces[nodeIndex(info.from)];
        if (!lt.vcd) continue;
        links_[j]->setTrace(lt);
        tracedLinks_.push_back(links_[j].get());
    }
    for (size_t u = 0; u < units_.size(); ++u) {
        const std::string scope = "frame_buffer.unit_" + std::to_string(u);
        FrameBufferUnit::Trace t{&v, v.declare(scope, "busy", K::Bit), v.declare(scope, "contributions", K::Integer)};
        if (u == 0) t.credit = v.declare(scope, "credit", K::Real);  // the share of the frame's credit back
        units_[u].enableTrace(t);
    }
    if (cfg_.balance.policy != "none")  // each boundary: its position and slides, moved by the node giving
        for (const BoundaryHistory& h : boundaryHistories()) {
            const std::string scope = "boundaries.col_" + std::to_string(h.column[0]) + "_" +
                                      std::to_string(h.column[1]) + "_b" + std::to_string(h.index);
            const int pos = v.declare(scope, "position", K::Real), slides = v.declare(scope, "slides", K::Integer);
            v.setReal(0, pos, h.positions[0].second);
            const int ax = cfg_.balance.axis, a = (ax + 1) % 3, b = (ax + 2) % 3;
            Cell below{}, above{};
            below[a] = above[a] = h.column[0];
            below[b] = above[b] = h.column[1];
            below[ax] = h.index - 1;
            above[ax] = h.index;
            traces[nodeIndex(below)].position[1] = traces[nodeIndex(above)].position[0] = pos;
            traces[nodeIndex(below)].slides[1] = traces[nodeIndex(above)].slides[0] = slides;
        }
    for (size_t i = 0; i < nodes_.size(); ++i) nodes_[i].enableTrace(traces[i]);
    v.setHorizon([this] { return traceHorizon(); });
    v.open(cfg_.vcdPath, cfg_.traceFrom, cfg_.traceTo);
}

// Every change before this time is recorded: processes record at their
// own time, never behind the kernel's, and so do links, except those with
// a control lane, which record a message when it is consumed, at times
// from its sending on (Link::traceStart).
Picos Machine::traceHorizon() const {
    Picos h = sc_core::sc_time_stamp().value();
    for (const Link* l : tracedLinks_)
        if (l->tracesLate()) h = std::min(h, l->oldestSent());
    return h;
}

void Machine::closeTraces() {
    if (!vcd_) return;
    const Picos end = frameEnd();
    vcd_->close(end, stall_.empty() ? "" : "incomplete: " + stall_);
    writeGtkw(gtkwPathFor(cfg_.vcdPath), cfg_.vcdPath, *vcd_, cfg_.traceFrom, std::min(cfg_.traceTo, end));
}

MachineResult runMachine(const Scene& scene, const MachineConfig& config) {
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    const auto t0 = std::chrono::steady_clock::now();
    Machine machine("machine", scene, config);
    try {
        sc_core::sc_start();
    } catch (const sc_core::sc_report& e) {
        // An exception thrown in a process comes out wrapped in a report of
        // several lines; its own message is the one line to show.
        throw std::runtime_error(e.get_msg());
    }
    machine.endFrame();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    machine.checkConservation();
    machine.closeTraces();
    return machine.collect(wall);
}

}  // namespace rt
