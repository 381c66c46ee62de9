// A node's busy time computed by a test from its operation counts (the
// counts are checked against rtref's elsewhere): each count times its cost
// (doc/machine.md, "Costs"), plus `extra` (grid updates), at the node's
// speed, rounded once (exact for one step, or at speed 1).
#pragma once
#include <cmath>

#include "node/node.h"

namespace rt::test {

// A cost set with every cost distinct and none a multiple of another's
// (sphere 7, polygon 11, cone 13, voxel 3, ray generation 17, shade 19,
// send 23, receive 29 ns), so a count charged at the wrong cost, or not at
// all, shows in the total.
inline Costs distinctCosts() {
    Costs c;
    c.test = {7000, 11000, 13000};
    c.voxelStep = 3000;
    c.rayGen = 17000;
    c.shade = 19000;
    c.send = 23000;
    c.recv = 29000;
    return c;
}

inline Picos busyByHand(const NodeStats& n, const Costs& c, double speed, Picos extra = 0) {
    const Counters& k = n.counters;
    const Picos ps = k.tests[0] * c.test[0] + k.tests[1] * c.test[1] + k.tests[2] * c.test[2] +
                     k.voxelSteps * c.voxelStep + n.raysGenerated * c.rayGen + k.shadings * c.shade +
                     n.messagesSent * c.send + n.messagesReceived * c.recv + extra;
    return Picos(std::llround(double(ps) / speed));
}

}  // namespace rt::test
