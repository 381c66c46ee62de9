// Where a node's busy time went, by kind of work (the report's
// busy_by_category; doc/report.md): each step's cost split into the
// operations it was charged for (cost_model.h), in whole picoseconds that
// sum to the step's cost exactly, so that a node's parts sum to its busy
// time exactly, through speed factors and frame ends alike. Waiting and
// being blocked on a full output buffer are not busy time: they are the
// node's wait (blocked_ns).
#pragma once
#include <array>
#include <cstdint>

#include "shape.h"
#include "base/units.h"

namespace rt {

// The kinds: intersection tests by primitive (PrimitiveKind order), then
// the rest. Messages are split by what they carry: rays and contributions
// (a tracing step's) against balancing's (a control step's: load reports,
// slides, acks, slabs).
enum BusyKind : int {
    kVoxelSteps = kPrimitiveKinds,
    kRayGeneration,
    kShading,
    kSend,
    kReceive,
    kBalancingSend,
    kBalancingReceive,
    kSlabRebuild,
    kBusyKinds
};
using BusyParts = std::array<Picos, kBusyKinds>;

// The report's name of a kind: "test_sphere", ..., "voxel_steps", ...
const char* busyKindName(int k);

Picos sumOf(const BusyParts& p);
BusyParts& operator+=(BusyParts& a, const BusyParts& b);
BusyParts& operator-=(BusyParts& a, const BusyParts& b);

// Parts in proportion to `p` that sum to `target` exactly (largest
// remainders, ties to the lower kind): a step's exact parts at a speed
// factor, or the share of a step that ran before the frame's end. With `p`
// all zero, everything goes to `fallback`.
BusyParts scaledTo(const BusyParts& p, Picos target, int fallback = kVoxelSteps);

// Takes `amount` out of `total`: first from the share `last` (the last
// step's parts) stands for, then, if it is more, from all of `total` in
// proportion. For a node whose last steps ran past the frame's end.
void trim(BusyParts& total, const BusyParts& last, Picos amount);

}  // namespace rt
