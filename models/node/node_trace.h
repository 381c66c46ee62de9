// What the VCD shows of one node (tracing is switched on per node): its
// busy and wait bits, its queue depth, and the position and slide count of
// the boundaries it gives slabs across. The node records each change at its
// own time into the machine's VcdStream (vcd_stream.h).
#pragma once
#include <array>

#include "trace/vcd_stream.h"

namespace rt {

struct NodeTrace {
    VcdStream* vcd = nullptr;
    int busy = -1, wait = -1, queue = -1;
    // Per side (0: lower, 1: upper face along the balancing axis): the
    // boundary's signals, -1 if it has none.
    std::array<int, 2> position{-1, -1}, slides{-1, -1};
};

}  // namespace rt
