#include "config/machine_config.h"

#include "channel/message.h"
#include "config/policy_table.h"
#include "base/units.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rt {

PolicyChoice recommendedPolicy(const std::array<int, 3>& dims, int axis) {
    const int length = dims[size_t(axis)];
    const std::string column = "columns of " + std::to_string(length) + (length == 1 ? " box" : " boxes");
    // (One box a column has no face along the axis to move: sample would
    // only send its sample's rays first, and that order alone made balls-3
    // on 64x1x1 along z 1.030 of the unbalanced frame.)
    if (length == 1) return {"none", "none: " + column + ": no boundary along the axis to move"};
    if (length <= kLongestColumnSampled)
        return {"sample", "sample: " + column + " (at most " + std::to_string(kLongestColumnSampled) + ")"};
    return {"measured", "measured: " + column + " (more than " + std::to_string(kLongestColumnSampled) +
                            "): the first frame keeps its split"};
}

// The policy as the user chose it: by name, or --balance recommended's choice and why.
std::string BalanceConfig::named() const {
    const size_t why = recommendedWhy.find(": ");
    return "'" + policy + "'" + (why == std::string::npos ? "" : " (--balance recommended's choice: " + recommendedWhy.substr(why + 2) + ")");
}

bool BalanceConfig::dynamic() const {
    const PolicyInfo* p = findPolicy(policy);
    return p && p->kind == PolicyKind::Dynamic;
}

double BalanceConfig::gainOf() const {
    if (gain > 0) return gain;
    const PolicyInfo* p = findPolicy(policy);
    return p ? p->defaultGain : 0.0;
}

double MachineConfig::speedOf(const Cell& c) const {
    auto it = nodeSpeed.find(c);
    return it == nodeSpeed.end() ? speed : it->second;
}

const Costs& MachineConfig::costsOf(const Cell& c) const {
    auto it = nodeCosts.find(c);
    return it == nodeCosts.end() ? costs : it->second;
}

const LinkParams& MachineConfig::linkOf(const Cell& from, int dir) const {
    auto it = linkOverride.find({from, dir});
    return it == linkOverride.end() ? link : it->second;
}

LinkParams MachineConfig::meshLinkOf(const Cell& from, int dir) const {
    LinkParams p = linkOf(from, dir);
    if (hopsByLinks) {
        p.engine = costsOf(from).send;
        p.latency += costsOf(neighbour(from, dir)).recv;
    }
    return p;
}

LinkParams MachineConfig::fbPortOf(const Cell& from) const {
    LinkParams p = fbPort;
    if (hopsByLinks) p.engine = costsOf(from).send;  // a unit's work is --cost-host
    return p;
}

Costs MachineConfig::processorCostsOf(const Cell& c) const {
    Costs k = costsOf(c);
    if (hopsByLinks) k.send = k.recv = 0;
    return k;
}

Picos MachineConfig::lookahead() const {
    const uint32_t mesh = smallestMeshMessage(balance.dynamic());
    Picos l = kMaxSimTime;
    auto meshLink = [&](const LinkParams& p) {
        l = std::min(l, linkLookahead(p, mesh));
        if (balance.dynamic() && p.controlDepth > 0) l = std::min(l, p.latency);  // its sender's (Machine::setLookaheads)
    };
    if (!hopsByLinks) {  // the links are the same everywhere but the overrides
        l = linkLookahead(fbPort, kSmallestFbMessage);
        meshLink(link);
        for (const auto& [where, p] : linkOverride) meshLink(p);
        return l;
    }
    for (int i = 0; i < nodeCount(); ++i) {
        const Cell c = cellAt(size_t(i), dims);
        l = std::min(l, linkLookahead(fbPortOf(c), kSmallestFbMessage));
        for (int d = 0; d < kDirs; ++d)
            if (inMesh(neighbour(c, d), dims)) meshLink(meshLinkOf(c, d));
    }
    return l;
}

const std::string& startMixHelp() {
    static const std::string help =
        "median and sample start with each column's boundaries at the quantiles of this share of its objects' centres "
        "plus the rest of its length (1: the object median; 0: the uniform split); auto: median 1; sample 1 where an "
        "intersection test costs at least a third of a ray's hop (weighing where the primary rays enter the world by a "
        "ray's generation against " + std::to_string(kTestsPerGeneration) + " tests), else 0.5 (below a tenth of a hop, "
        "of all the objects: the same planes in every column, 0 where they do not lighten the heaviest box by more than " +
        std::to_string(kSpreadsLighter) + " standard deviations of an even spread's; 0 in a column whose heaviest box "
        "by objects 0.5 leaves as heavy; and 0 where it leaves the heaviest box reaching into as many objects, whose "
        "centres it holds or not), 0 where a hop's wire time is at least " + std::to_string(kWirePerHandling) +
        " times its handling, 0 where 0.5's busiest box's primary rays would keep its link " +
        formatNumber(kLinkOverUniformFrame) + " times longer than the uniform split's frame (a ray's work in the "
        "heaviest box: its handling and " + std::to_string(kTestsPerRayInHeaviestBox) + " tests), and 0 on columns of "
        "more than " + std::to_string(kLongestColumnStartedByObjects) + " boxes";
    return help;
}

std::string onlySampleGathers(const std::string& named) { return "only sample gathers a sample, not " + named; }

const std::string& sampleLinksHelp() {
    static const std::string help =
        "sample only, on columns of at most " + std::to_string(kLongestColumnSampled) + " boxes, not with --boundaries-from (given on "
        "elsewhere, refused): on, the sample also "
        "counts where its rays cross the column (a third value a cell in the sum's message, so fewer cells), and no part "
        "of a split is cheaper than its link up, the sample's rays across its upper plane on the wire; off, the work alone";
    return help;
}

namespace {

// Each row's value in its range (base/param.h), as the command line checks
// it: a configuration built in code is checked alike. `flag`: the flags'
// prefix ("--", "--link-", ...).
template <class S>
void checkRanges(const std::vector<Param<S>>& rows, const S& s, const std::string& flag) {
    for (const Param<S>& p : rows) {
        const std::string name = flag + p.name;
        if (p.kind == ParamKind::Count) {
            const int v = fieldOf<int>(p, s);
            if (p.word && v == p.wordValue) continue;  // ("auto": chosen where it is used)
            if (v < p.lo || v > p.hi) throw std::invalid_argument(name + ": must be in " + formatNumber(p.lo) + ".." + formatNumber(p.hi));
        } else if (p.kind == ParamKind::Real) {
            const double v = fieldOf<double>(p, s);
            if (p.word && v == p.wordValue) continue;  // ("auto": chosen where it is used)
            if (!std::isfinite(v) || (p.openBelow ? !(v > p.lo) : !(v >= p.lo)) || v > p.hi)
                throw std::invalid_argument(name + (p.openBelow ? ": must be above " : ": must be at least ") + formatNumber(p.lo) +
                                            (std::isinf(p.hi) ? "" : " and at most " + formatNumber(p.hi)));
        } else if (p.kind == ParamKind::Rate) {
            const double v = fieldOf<double>(p, s);
            if (!(v > 0) || !std::isfinite(v)) throw std::invalid_argument(name + ": must be positive and finite");
        }
    }
}

void checkLink(const LinkParams& l, const std::string& flag) { checkRanges(linkParams(), l, flag); }

}  // namespace

Picos MachineConfig::watchdogSpanOrDefault(size_t objects) const {
    if (watchdogSpan) return watchdogSpan;
    // 1,000 times the longest single thing a running frame waits for: a
    // message's latency and time on the wire (the largest message: a full
    // batch of rays or of contributions), a unit's work on one, a node's step
    // (at worst every object tested once, at the slowest node's speed).
    const uint32_t bytes = std::max(kHeaderBytes + uint32_t(rayBatch) * kRayBytes, kHeaderBytes + uint32_t(fbBatch) * kContributionBytes);
    double longest = double(hostCost) * fbBatch;
    auto link = [&](const LinkParams& l) { longest = std::max(longest, double(l.latency) + wirePicos(l, bytes)); };
    link(this->link);
    link(fbPort);
    for (const auto& [where, l] : linkOverride) link(l);
    double slowest = speed;
    for (const auto& [cell, f] : nodeSpeed) slowest = std::min(slowest, f);
    auto step = [&](const Costs& c) {  // every object tested, and each other cost once
        const Picos test = *std::max_element(c.test.begin(), c.test.end());
        double t = double(objects) * double(test);
        for (const Param<Costs>& p : costParams()) t += double(fieldOf<Picos>(p, c));
        for (const Picos x : c.test) t -= double(x);
        longest = std::max(longest, t / slowest);
    };
    step(costs);
    for (const auto& [cell, c] : nodeCosts) step(c);
    const double span = std::max(1e8, 1000 * longest);  // at least 100 us
    return span >= double(kMaxSimTime / 4) ? kMaxSimTime / 4 : Picos(span);
}

namespace {

// `c` is a node of the mesh; with `dir`, one with a link that way.
void checkNode(const Cell& c, const std::array<int, 3>& dims, const std::string& flag, int dir = -1) {
    if (!inMesh(c, dims)) throw std::invalid_argument(flag + ": node outside the mesh");
    if (dir >= 0 && dir < kDirs && !inMesh(neighbour(c, dir), dims))
        throw std::invalid_argument(flag + ": no link in that direction (mesh face)");
}

}  // namespace

void MachineConfig::validate() const {
    for (int a = 0; a < 3; ++a)
        if (dims[a] < 1 || dims[a] > kMaxNodesPerAxis)
            throw std::invalid_argument("--mesh: nodes per axis must be in 1.." + std::to_string(kMaxNodesPerAxis));
    if (long(dims[0]) * dims[1] * dims[2] > kMaxNodes)
        throw std::invalid_argument("--mesh: at most " + std::to_string(kMaxNodes) + " nodes (32 x 32 x 32), not " +
                                    std::to_string(long(dims[0]) * dims[1] * dims[2]));
    if (width < 0 || height < 0) throw std::invalid_argument("--size: must be positive");
    checkRanges(machineParams(), *this, "--");
    for (const auto& [c, s] : nodeSpeed) {
        if (!(s > 0) || !std::isfinite(s)) throw std::invalid_argument("--node-speed: must be positive");
        checkNode(c, dims, "--node-speed");
    }
    for (const auto& [c, k] : nodeCosts) checkNode(c, dims, "--node-cost");
    checkLink(link, "--link-");
    checkLink(fbPort, "--fb-");
    for (const auto& [key, l] : linkOverride) {
        checkLink(l, "--link-set " + cellText(key.first) + "," + dirName(key.second) + " ");
        checkNode(key.first, dims, "--link-set", key.second);
    }
    for (const Cell& c : traceNodes) checkNode(c, dims, "--trace-nodes");
    for (const auto& [c, d] : traceLinks) checkNode(c, dims, "--trace-links", d);
    if (traceFrom > traceTo) throw std::invalid_argument("--trace-window: start after end");
    balance.validate(std::max<Picos>(1000, costs.send + costs.recv), !startBoundaries.empty() || !targetBoundaries.empty());
    const std::string rung = relayRung();
    if (usesRelay() && !balance.boxesStayPut())
        throw std::invalid_argument("--fidelity: " + rung + " needs boxes that stay put within and between frames (--balance "
                                    "none or median), not --balance " + balance.asGiven());
    if (expressRoutes && !balance.boxesStayPut())
        throw std::invalid_argument("--max-error: a calibration that may switch express on needs boxes that stay put, not --balance " +
                                    balance.asGiven());
    if (pixelStride < 1) throw std::invalid_argument("pixel stride: must be at least 1, not " + std::to_string(pixelStride));
    if (usesRelay() && rayBatch > 1)
        throw std::invalid_argument("--fidelity: " + rung + " sends a ray per message, not with --ray-batch " + std::to_string(rayBatch));
}

void BalanceConfig::validate(Picos reportFloor, bool carriedBoundaries) const {
    if (axis < 0 || axis > 2) throw std::invalid_argument("--axis: must be x, y or z");
    if (interval == 0) throw std::invalid_argument("--balance-interval: must be positive");
    // An interval a node cannot honour: every interval wakes every node and
    // sends a report each way, so one shorter than handling a report (or
    // than 1 ns) only burns the run's time and memory, until the run runs out
    // of memory.
    if (dynamic() && interval < reportFloor)
        throw std::invalid_argument("--balance-interval: " + formatTime(interval) +
                                    " is shorter than a node takes to send and take a load report (" +
                                    formatTime(reportFloor) + ": --cost-send + --cost-recv, at least 1 ns)");
    if (!findPolicy(policy)) throw std::invalid_argument("--balance: no policy named '" + policy + "'");
    const std::string named = this->named();
    // The layer's planes apply the paper's rule (ideal_layer_faces.h) and
    // start in line: one frame of slide (or resplit, whose first frame is slide).
    if (idealLayerFaces && policy != "slide" && policy != "resplit")
        throw std::invalid_argument("--faces ideal-layer: applies slide's rule to the layers; needs --balance slide (or resplit, one frame), not " +
                                    named);
    if (idealLayerFaces && carriedBoundaries)
        throw std::invalid_argument("--faces ideal-layer: needs every column's faces in line at the start (one frame, "
                                    "no --boundaries-from)");
    checkRanges(balanceParams(), *this, "--");
    if (sampleCredit && policy != "sample") throw std::invalid_argument("--sample-end credit: " + onlySampleGathers(named));
    if (startMix != kStartMixAuto && !startsAtObjects())  // (after the ranges: a nan is named as a bad value)
        throw std::invalid_argument("--start-mix " + formatNumber(startMix) + ": only median and sample start at a split of their own; " + named +
                                    " starts at the uniform split");
}

}  // namespace rt
