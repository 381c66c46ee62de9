// Where a cost is charged: what a node's work costs in time. A step's time
// is its operation counts times their costs (--cost-*, per node
// --node-cost), divided by the node's speed factor (--speed, --node-speed);
// a slide adds a grid update per object moved (--cost-rebuild). Every time
// a node spends comes from here (doc/machine.md, "Costs and their
// defaults"); the node adds it to its local time (Node::chargeAndSend).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "node/busy_parts.h"
#include "counters.h"
#include "config/machine_config.h"

namespace rt {

class CostModel {
public:
    CostModel(const Costs& costs, double speed, Picos rebuildPerObject)
        : costs_(costs), speed_(speed), rebuild_(rebuildPerObject), safeOps_(kMaxSimTime / std::max<Picos>(1, largest(costs))) {}

    // A step: the operations counted from `before` to `after`, the
    // messages it sent and received and the primary rays it generated.
    Picos step(const Counters& before, const Counters& c, uint64_t sends, uint64_t recvs, uint64_t generated) const {
        return atSpeed(sumOf(operationParts(before, c, sends, recvs, generated)));
    }
    // The same step's cost by kind of work (busy_parts.h): parts that sum to
    // step(...) exactly.
    BusyParts stepParts(const Counters& before, const Counters& c, uint64_t sends, uint64_t recvs, uint64_t generated) const {
        const BusyParts p = operationParts(before, c, sends, recvs, generated);
        if (speed_ == 1.0) return p;  // (at speed 1 the parts are the sum: a node's every step came here)
        return scaledTo(p, atSpeed(sumOf(p)));
    }
    // A step of messages alone: its messages' handling (balancing's, or a
    // flush of rays and contributions) and the grid update for `objects`
    // moved; they sum to step(c, c, sends, recvs, 0) + rebuild(objects).
    BusyParts messageParts(uint64_t sends, uint64_t recvs, uint64_t objects, bool balancing) const {
        const Counters none{};
        BusyParts p = stepParts(none, none, sends, recvs, 0);
        if (balancing) {
            p[kBalancingSend] = std::exchange(p[kSend], 0);
            p[kBalancingReceive] = std::exchange(p[kReceive], 0);
        }
        p[kSlabRebuild] = rebuild(objects);
        return p;
    }
    // Updating the node's grid for `objects` moved in or out by a slide.
    Picos rebuild(uint64_t objects) const {
        timesCount(rebuild_, objects, "a grid update for the objects a slide moved (--cost-rebuild)");
        return atSpeed(objects * rebuild_);
    }
    // The guard's estimate of handling a slab of `objects` on both nodes
    // (a send, a receive and both grid updates), unrounded.
    double slabHandling(uint64_t objects) const { return double(costs_.send + costs_.recv + 2 * objects * rebuild_) / speed_; }

private:
    // Each kind's operations times its cost, before the speed factor.
    BusyParts operationParts(const Counters& before, const Counters& c, uint64_t sends, uint64_t recvs,
                             uint64_t generated) const {
        // (Past safeOps_ operations their sum could wrap: summed apart, checked.)
        if (operations(before, c) + sends + recvs + generated > safeOps_) checkStep(before, c, sends, recvs, generated);
        BusyParts p{};
        p[kSend] = sends * costs_.send;
        p[kReceive] = recvs * costs_.recv;
        p[kRayGeneration] = generated * costs_.rayGen;
        for (int k = 0; k < kPrimitiveKinds; ++k) p[size_t(k)] = (c.tests[k] - before.tests[k]) * costs_.test[k];
        p[kVoxelSteps] = (c.voxelSteps - before.voxelSteps) * costs_.voxelStep;
        p[kShading] = (c.shadings - before.shadings) * costs_.shade;
        return p;
    }
    // Exact when the speed is 1; otherwise rounded to the nearest picosecond
    // (and checked: a slow node's step can pass the counter).
    Picos atSpeed(Picos ps) const {
        if (speed_ == 1.0) return ps;
        const double t = double(ps) / speed_;
        if (!(t <= double(kMaxSimTime))) throw std::runtime_error(pastTheCounter("at its speed factor (--speed, --node-speed)"));
        return Picos(std::llround(t));
    }
    static Picos largest(const Costs& c) {
        Picos m = std::max({c.send, c.recv, c.rayGen, c.voxelStep, c.shade});
        for (Picos t : c.test) m = std::max(m, t);
        return m;
    }
    static uint64_t operations(const Counters& before, const Counters& c) {
        uint64_t n = (c.voxelSteps - before.voxelSteps) + (c.shadings - before.shadings);
        for (int k = 0; k < kPrimitiveKinds; ++k) n += c.tests[k] - before.tests[k];
        return n;
    }
    void checkStep(const Counters& before, const Counters& c, uint64_t sends, uint64_t recvs, uint64_t generated) const {
        long double t = (long double)sends * costs_.send + (long double)recvs * costs_.recv + (long double)generated * costs_.rayGen +
                        (long double)(c.voxelSteps - before.voxelSteps) * costs_.voxelStep +
                        (long double)(c.shadings - before.shadings) * costs_.shade;
        for (int k = 0; k < kPrimitiveKinds; ++k) t += (long double)(c.tests[k] - before.tests[k]) * costs_.test[k];
        if (t > (long double)kMaxSimTime) throw std::runtime_error(pastTheCounter("(its operations times --cost-*)"));
    }
    static std::string pastTheCounter(const std::string& how) {
        return "a node's step would take longer than " + formatTime(kMaxSimTime) + " of simulated time " + how +
               " (the picosecond counter would wrap); are the costs meant to be this large?";
    }

    Costs costs_;
    double speed_;
    Picos rebuild_;
    uint64_t safeOps_;  // a step of at most this many operations cannot pass kMaxSimTime before atSpeed
};

}  // namespace rt
