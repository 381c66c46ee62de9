// Start-up's memory check (doc/robustness.md, "Memory"): what binning the
// scene into the nodes' grids takes, counted before a byte of it is
// allocated. Objects that overlap many cells (a few thousand large spheres)
// make a grid's references grow as their count squared, and each node of
// the mesh has its own grid over its own objects: a 50 KB scene once needed
// 3.8 GB at N = 2 and died of std::bad_alloc. rtsim refuses such a run with
// the estimate (exit 2) instead.
#pragma once
#include "config/machine_config.h"
#include "scene.h"

namespace rt {

struct BinningSize {
    double bytes = 0;           // every node's grid and objects, at the frame's start
    double largestGrid = 0;     // references in the largest grid
};

// The nodes' boxes and objects as Machine builds them at the frame's start.
BinningSize binningSize(const Scene& scene, const MachineConfig& cfg);

}  // namespace rt
