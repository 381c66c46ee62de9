// How far a run is from the possible: lower bounds on its render time that
// no balancing policy can beat in this model, from the run's own figures.
//
//   perfect       total node busy time / nodes: every node equally busy,
//                 no waiting (the best any balancer could do, with the work
//                 this run did);
//   column        the largest column's summed busy time / its length: a
//                 balancer that slides boundaries along one axis moves work
//                 only within a column of nodes along that axis, so the
//                 heaviest column can at best be spread evenly over its N
//                 nodes;
//   frame buffer  the busiest frame-buffer unit's busy time: the frame is not
//                 done before its last contribution is accumulated.
//
// Each is a bound for the work the run did: balancing itself adds work
// (forwarding through thinner boxes, slabs, reports), so the bounds of the
// unbalanced run are the ones to hold a balanced run against.
#pragma once
#include "machine/machine.h"

namespace rt {

struct Bounds {
    Picos perfect = 0, column = 0, frameBuffer = 0;
};

Bounds renderTimeBounds(const MachineResult& r, const MachineConfig& config);

}  // namespace rt
