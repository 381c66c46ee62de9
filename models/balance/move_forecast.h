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
// for them (doc/balancing.md, "The rule, and how it runs").
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

// The longest chain of handovers that moving each column's planes from
// `from` to `to` takes, in ns: per box a plane crosses, a slide's latency
// and handling on both nodes, and for each object between the plane's old
// and new place (the boxes' object counts in frame `r`, shared out by
// length, at their box's mean size) its bytes on the link and the grid
// updates on both nodes, once per box it is passed through (on average
// half the chain).
double moveNs(const FrameState& r, const MachineConfig& m, const InnerPlanes& from, const InnerPlanes& to);

// When each node's faces are in place (per column, per node along it: ns
// from the frame's start; 0 where they stay), the handovers followed event
// by event as the nodes make them (BalanceAgent::startAt): each node gives
// a slab towards its targets as far as its box allows and again after each
// take, one thing at a time. A give costs the giver its send and a grid
// update per object moved, then the slab's latency and wire time; the
// taker its receive, its acknowledgement's send and the same updates. So
// a plane that crosses k boxes
// waits for the planes on its way, and an object is updated at every box
// it passes. A slab's objects are counted from the scene's `objects` where
// given (those whose bounds reach into it), else from the boxes' counts in
// frame `r` shared out by length. The rays traced meanwhile are not in it.
// Why beside moveNs: on 33x1x1 the planes moved one after another, and the
// move took about 228 ms where the longest chain said 90.3
// (doc/balancing.md, "A move that would lose against not balancing").
// Throws std::invalid_argument where `r`, `from` or `to` are of another mesh.
InnerPlanes facesInPlaceNs(const FrameState& r, const MachineConfig& m, const InnerPlanes& from, const InnerPlanes& to,
                           const std::vector<Shape>* objects = nullptr);

}  // namespace rt
