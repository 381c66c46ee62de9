// What a run's processes need at once, counted before any of it is
// allocated (the binning of models/machine/binning_memory.h, the image, the nodes),
// and checked against what the process may use (sw/memory_estimate.h: the
// physical memory, the cgroup's limit, RLIMIT_AS). A run is more than its
// frame:
//  - --frames K: the frames run one at a time in this process, each on a
//    machine of its own with the same mesh and scene (each a frame's
//    memory, freed before the next);
//  - the reference runs (unless --no-baseline): with the frame still held,
//    two child processes at once, the same mesh balanced the other way (a
//    frame's memory again) and the 1x1x1 baseline (every object in one grid,
//    the whole image).
// The physical memory and the cgroup's limit are shared by all of them at
// once; RLIMIT_AS binds each process on its own.
#pragma once
#include <string>

#include "memory_estimate.h"
#include "rtsim_cli.h"
#include "scene.h"

namespace rt {

struct JobMemory {
    double frame = 0;        // one frame on the run's mesh: grids and objects, nodes, image (bytes)
    double comparison = 0;   // the balancing comparison run (0: none)
    double baseline = 0;     // the 1x1x1 baseline run (0: none)
    double grids = 0;        // of the frame: the nodes' grids and objects at the frame's start
    double largestGrid = 0;  // references in the largest grid of the run's mesh
    double together() const { return frame + comparison + baseline; }
    double perProcess() const { return frame > baseline ? frame : baseline; }
};

JobMemory jobMemory(const RtsimOptions& o, const Scene& scene);

// Throws SceneError naming the scene, the mesh and the limit if the job
// does not fit `limits`, or a grid would hold more references than it can.
void checkJobMemory(const RtsimOptions& o, const Scene& scene, const MemoryLimits& limits);

}  // namespace rt
