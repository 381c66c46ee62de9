// What getting to new planes costs at a frame's start (`resplit`,
// `measured`): the faces move by slab handovers (startAt), and a plane that
// crosses k boxes moves in a chain of k slides, one after the other, each
// carrying the slab's objects: the giver's and the taker's handling and
// grid updates for them, and their time on the link. The nodes whose faces
// move wait for them (a node generates its primary rays once its faces are
// at their targets). Plain C++ on reports (JSON), beside frame_forecast.h.
//
// Measured where it was missing (the built-in scene at 64x64, 33x1x1): the
// forecast for the re-split frame was 102.5 us, the frame 492 us; its
// busiest node spent 45.5 us updating its grid for slabs passed along
// chains of up to a dozen boxes (doc/balancing.md, "The rule, and how it
// runs").
#pragma once
#include <nlohmann/json.hpp>

#include "balance/frame_forecast.h"
#include "config/machine_config.h"

namespace rt {

// A slab's object on the wire, taken as a sphere's (objectBytes: 42 bytes).
constexpr double kSlabObjectBytes = 42;

// The longest chain of handovers that moving each column's planes from
// `from` to `to` takes, in ns: per box a plane crosses, a slide's latency
// and handling on both nodes, and for each object between the plane's old
// and new place (the boxes' object counts in report `r`, shared out by
// length) its bytes on the link and the grid updates on both nodes, once
// per box it is passed through (on average half the chain).
double moveNs(const nlohmann::json& r, const MachineConfig& m, const InnerPlanes& from, const InnerPlanes& to);

}  // namespace rt
