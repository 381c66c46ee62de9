// MachineConfig::checkDerivedTimes: the configuration's derived times,
// bounded before the run (doc/robustness.md, "Derived times"). A flag's
// value alone is at most 1,000 s (units.h); these are what the model makes
// of several: cost x count, bytes / bandwidth, time / speed.
#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "config/machine_config.h"
#include "base/mesh_geometry.h"
#include "channel/message.h"

namespace rt {
namespace {

// Throws unless `t` ps (a double: it may be far past any integer) is at
// most kMaxTimeValue.
void bound(double t, const std::string& flags, const std::string& what) {
    if (t <= double(kMaxTimeValue)) return;
    const std::string took = t >= double(kMaxSimTime) ? "more than " + formatTime(kMaxSimTime) : formatTime(Picos(t));
    throw std::invalid_argument(flags + ": " + what + " would take " + took +
                                ", more than 1,000 s (the most any one step of the model may take)");
}

void boundWire(const LinkParams& l, const std::string& flag, uint32_t bytes, const std::string& message) {
    bound(wirePicos(l, bytes), flag, message + " (" + std::to_string(bytes) + " bytes) at " + formatRate(l.bandwidth) + " on the wire");
}

// Every cost (costParams) at `speed`.
void boundCosts(const Costs& c, double speed, const std::string& speedFlag) {
    for (const Param<Costs>& p : costParams())
        bound(double(fieldOf<Picos>(p, c)) / speed, speedFlag + " with --cost-" + p.name, "one operation");
}

}  // namespace

void MachineConfig::checkDerivedTimes(size_t objects, uint32_t sumBytes) const {
    const uint32_t rays = kHeaderBytes + uint32_t(rayBatch) * kRayBytes;
    const uint32_t contributions = kHeaderBytes + uint32_t(fbBatch) * kContributionBytes;
    boundWire(link, "--link-bandwidth with --ray-batch", rays, "a full ray message");
    for (const auto& [where, l] : linkOverride)
        boundWire(l, "--link-set " + cellText(where.first) + "," + dirName(where.second), rays, "a full ray message");
    if (sumBytes > 0) {
        boundWire(link, "--link-bandwidth with --balance " + balance.policy, sumBytes, "a sample's sum");
        for (const auto& [where, l] : linkOverride)
            boundWire(l, "--link-set " + cellText(where.first) + "," + dirName(where.second), sumBytes, "a sample's sum");
    }
    boundWire(fbPort, "--fb-bandwidth with --fb-batch", contributions, "a full frame-buffer message");
    bound(double(hostCost) * fbBatch, "--cost-host with --fb-batch", "accumulating a full frame-buffer message");
    // Each node's costs at its speed.
    boundCosts(costs, speed, "--speed " + formatNumber(speed));
    for (const auto& [cell, c] : nodeCosts) boundCosts(c, speedOf(cell), "--node-cost " + cellText(cell) + " at its speed");
    for (const auto& [cell, f] : nodeSpeed) boundCosts(costsOf(cell), f, "--node-speed " + cellText(cell) + "=" + formatNumber(f));
    if (!balance.dynamic()) return;
    double slowest = speed;
    for (const auto& [cell, f] : nodeSpeed) slowest = std::min(slowest, f);
    bound(double(balance.rebuildCost) * double(objects) / slowest, "--cost-rebuild",
          "a slide's grid update for all " + std::to_string(objects) + " objects at speed " + formatNumber(slowest));
    // A load report on a control lane waits its time on the wire divided by
    // --report-share before the next (balance_agent.cpp).
    auto paced = [&](const LinkParams& l, const std::string& flag) {
        if (l.controlDepth > 0)
            bound(wirePicos(l, kHeaderBytes + kLoadReportBytes) / balance.reportShare, flag + " with --report-share",
                  "the gap between two load reports");
    };
    paced(link, "--link-bandwidth");
    for (const auto& [where, l] : linkOverride) paced(l, "--link-set " + cellText(where.first) + "," + dirName(where.second));
}

}  // namespace rt
