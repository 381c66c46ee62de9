// What the watchdog (machine.h) watches: the latest simulated time at which
// a ray, a contribution or credit moved (a node traced a ray, or a link took
// a ray, contribution, credit or frame-buffer message). Balancing messages
// do not count: a run whose only traffic is load reports is stuck.
#pragma once
#include "units.h"

namespace rt {

struct Progress {
    Picos last = 0;
    void mark(Picos t) {
        if (t > last) last = t;
    }
};

}  // namespace rt
