// What getting to new planes costs at a frame's start (`resplit`,
// `measured`): the faces move by slab handovers (startAt), and a plane that
// crosses k boxes moves in a chain of k slides, one after the other, each
// carrying the slab's objects: the giver's and the taker's handling and
// grid updates for them, and their time on the link. The nodes whose faces
// move wait for them (a node generates its primary rays once its faces are
// at their targets). Beside frame_forecast.h, on the same frame state.
//
// Without it a forecast can miss by a factor: on a long column the slabs
// pass along chains of boxes, and each box on the chain updates its grid
// for them; and the planes move one after another, each waiting for the
// one below (doc/balancing.md, "The rule, and how it runs").
#pragma once
#include "balance/frame_forecast.h"
#include "config/machine_config.h"

namespace rt {

// A slab's object on the wire where the frame state does not say its
// boxes' objects' sizes: a sphere's (objectBytes: 42 bytes). A polygon of
// gears-2 averages about 155.
constexpr double kSlabObjectBytes = 42;

// One plane's chain of handovers from `a` to `b` along a column whose
// boxes are {lo, hi, passPs, boxes}: per box the move crosses, `hopPs` (a
// slide's latency and handling on both nodes), and each object between a
// and b (the box's passPs, what passing all its objects on one box costs,
// shared out by length) passed on through on average half the chain. In
// ps. `sample`'s top node prices its move with it too (sample_split.h),
// where an entry may stand for a group of `boxes` boxes of even length.
struct BoxPass {
    double lo, hi, passPs, boxes = 1;
};
double chainPs(const std::vector<BoxPass>& boxes, double a, double b, double hopPs);

// How long moving each column's planes from `from` to `to` takes, in ns:
// the slowest column's handovers, followed event by event as the nodes
// make them (a plane that crosses k boxes waits for the planes below or
// above it, and each object is updated at every box it passes): per give,
// the giver's send and grid updates, the slab's latency and bytes on the
// link, the taker's receive and grid updates. The objects a slab carries
// are counted from `objects` (the scene's) where given, else from the
// boxes' counts in frame `r`, shared out by length.
double moveNs(const FrameState& r, const MachineConfig& m, const InnerPlanes& from, const InnerPlanes& to,
              const std::vector<Shape>* objects = nullptr);

}  // namespace rt
