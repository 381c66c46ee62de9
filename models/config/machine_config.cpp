#include "config/machine_config.h"

#include "channel/message.h"
#include "config/policy_table.h"
#include "base/units.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rt {

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

static void checkLink(const LinkParams& l, const std::string& flag) {
    if (!(l.bandwidth > 0) || !std::isfinite(l.bandwidth))
        throw std::invalid_argument(flag + ": bandwidth must be positive and finite");
    if (l.depth < 1 || l.depth > 1000000) throw std::invalid_argument(flag + ": depth must be in 1..1000000");
    if (l.controlDepth < 0 || l.controlDepth > 1000000) throw std::invalid_argument(flag + ": control depth must be in 0..1000000");
    if (l.outDepth < 0 || l.outDepth > 1000000) throw std::invalid_argument(flag + ": output depth must be in 0..1000000");
}

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
    auto step = [&](const Costs& c) {
        const Picos test = *std::max_element(c.test.begin(), c.test.end());
        const double t = double(objects) * double(test) + double(c.rayGen + c.shade + c.send + c.recv);
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
    if (maxDepth < 0 || maxDepth > 39) throw std::invalid_argument("--max-depth: must be in 0..39");
    if (!(speed > 0) || !std::isfinite(speed)) throw std::invalid_argument("--speed: must be positive");
    for (const auto& [c, s] : nodeSpeed) {
        if (!(s > 0) || !std::isfinite(s)) throw std::invalid_argument("--node-speed: must be positive");
        checkNode(c, dims, "--node-speed");
    }
    for (const auto& [c, k] : nodeCosts) checkNode(c, dims, "--node-cost");
    checkLink(link, "--link-bandwidth/--link-depth");
    checkLink(fbPort, "--fb-bandwidth/--fb-depth");
    for (const auto& [key, l] : linkOverride) {
        checkLink(l, "--link-set");
        checkNode(key.first, dims, "--link-set", key.second);
    }
    if (fbUnits < 1 || fbUnits > 256) throw std::invalid_argument("--fb-units: must be in 1..256");
    if (fbBatch < 1 || fbBatch > 65536) throw std::invalid_argument("--fb-batch: must be in 1..65536");
    if (rayBatch < 1 || rayBatch > 65536) throw std::invalid_argument("--ray-batch: must be in 1..65536");
    for (const Cell& c : traceNodes) checkNode(c, dims, "--trace-nodes");
    for (const auto& [c, d] : traceLinks) checkNode(c, dims, "--trace-links", d);
    if (traceFrom > traceTo) throw std::invalid_argument("--trace-window: start after end");
    balance.validate(std::max<Picos>(1000, costs.send + costs.recv), !startBoundaries.empty() || !targetBoundaries.empty());
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
    // The layer's planes apply the paper's rule (ideal_layer_faces.h) and
    // start in line: one frame of slide (or resplit, whose first frame is slide).
    if (idealLayerFaces && policy != "slide" && policy != "resplit")
        throw std::invalid_argument("--faces ideal-layer: applies slide's rule to the layers; needs --balance slide (or resplit, one frame), not '" +
                                    policy + "'");
    if (idealLayerFaces && carriedBoundaries)
        throw std::invalid_argument("--faces ideal-layer: needs every column's faces in line at the start (one frame, "
                                    "no --boundaries-from)");
    auto atLeast0 = [](double x) { return x >= 0 && std::isfinite(x); };
    if (!atLeast0(gain)) throw std::invalid_argument("--gain: must be positive (0: the policy's)");
    if (!atLeast0(maxAge)) throw std::invalid_argument("--max-age: must be non-negative");
    if (!atLeast0(horizon)) throw std::invalid_argument("--guard-horizon: must be non-negative");
    if (!atLeast0(hopRatio)) throw std::invalid_argument("--guard-hop: must be non-negative");
    if (!atLeast0(wireShare)) throw std::invalid_argument("--guard-wire: must be non-negative (0: off)");
    if (!(reportShare > 0) || !(reportShare <= 1)) throw std::invalid_argument("--report-share: must be in (0, 1]");
    if (!(deadband >= 0) || !(deadband < 1)) throw std::invalid_argument("--deadband: must be in [0, 1)");
    if (!(minThickness > 0) || !(minThickness <= 1)) throw std::invalid_argument("--min-thickness: must be in (0, 1]");
    if (bins < 1 || bins > 4096) throw std::invalid_argument("--bins: must be in 1..4096");
}

}  // namespace rt
