// Where a cost is charged: what a node's work costs in time. A step's time
// is its operation counts times their costs (--cost-*, per node
// --node-cost), divided by the node's speed factor (--speed, --node-speed);
// a slide adds a grid update per object moved (--cost-rebuild). Every time
// a node spends comes from here (doc/machine.md, "Costs and their
// defaults"); the node adds it to its local time (Node::chargeAndSend).
#pragma once
#include <cmath>
#include <cstdint>

#include "counters.h"
#include "machine_config.h"

namespace rt {

class CostModel {
public:
    CostModel(const Costs& costs, double speed, Picos rebuildPerObject)
        : costs_(costs), speed_(speed), rebuild_(rebuildPerObject) {}

    // A step: the operations counted from `before` to `after`, the
    // messages it sent and received and the primary rays it generated.
    Picos step(const Counters& before, const Counters& c, uint64_t sends, uint64_t recvs, uint64_t generated) const {
        Picos ps = sends * costs_.send + recvs * costs_.recv + generated * costs_.rayGen;
        for (int k = 0; k < kPrimitiveKinds; ++k) ps += (c.tests[k] - before.tests[k]) * costs_.test[k];
        ps += (c.voxelSteps - before.voxelSteps) * costs_.voxelStep;
        ps += (c.shadings - before.shadings) * costs_.shade;
        return atSpeed(ps);
    }
    // Updating the node's grid for `objects` moved in or out by a slide.
    Picos rebuild(uint64_t objects) const { return atSpeed(objects * rebuild_); }
    // The guard's estimate of handling a slab of `objects` on both nodes
    // (a send, a receive and both grid updates), unrounded.
    double slabHandling(uint64_t objects) const { return double(costs_.send + costs_.recv + 2 * objects * rebuild_) / speed_; }

private:
    // Exact when the speed is 1; otherwise rounded to the nearest picosecond.
    Picos atSpeed(Picos ps) const {
        if (speed_ == 1.0) return ps;
        return Picos(std::llround(double(ps) / speed_));
    }

    Costs costs_;
    double speed_;
    Picos rebuild_;
};

}  // namespace rt
