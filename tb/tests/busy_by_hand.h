// A node's busy time computed by a test from its operation counts (the
// counts are checked against rtref's elsewhere): each count times its cost
// (doc/machine.md, "Costs"), plus `extra` (grid updates), at the node's
// speed, rounded once (exact for one step, or at speed 1).
#pragma once
#include <cmath>

#include "node.h"

namespace rt::test {

inline Picos busyByHand(const NodeStats& n, const Costs& c, double speed, Picos extra = 0) {
    const Counters& k = n.counters;
    const Picos ps = k.tests[0] * c.test[0] + k.tests[1] * c.test[1] + k.tests[2] * c.test[2] +
                     k.voxelSteps * c.voxelStep + n.raysGenerated * c.rayGen + k.shadings * c.shade +
                     n.messagesSent * c.send + n.messagesReceived * c.recv + extra;
    return Picos(std::llround(double(ps) / speed));
}

}  // namespace rt::test
