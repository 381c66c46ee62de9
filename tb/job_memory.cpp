#include "job_memory.h"

#include <cstdint>

#include "machine/binning_memory.h"
#include "grid.h"
#include "messages.h"
#include "scene_error.h"

namespace rt {
namespace {

// One frame of `m`'s mesh: its grids and objects, its nodes, the image.
double frameBytes(const BinningSize& b, const MachineConfig& m) {
    return b.bytes + kRtsimBytesPerPixel * m.width * m.height + kRtsimBytesPerNode * double(m.nodeCount());
}

}  // namespace

JobMemory jobMemory(const RtsimOptions& o, const Scene& scene) {
    const BinningSize b = binningSize(scene, o.machine);
    JobMemory j;
    j.frame = frameBytes(b, o.machine);
    j.grids = b.bytes;
    j.largestGrid = b.largestGrid;
    const bool single = o.machine.dims == std::array<int, 3>{1, 1, 1};
    if (!o.baseline) return j;  // (a reference run has none of its own)
    if (o.machine.dims[size_t(o.machine.balance.axis)] > 1) j.comparison = j.frame;  // the same mesh and scene
    if (!single) {
        MachineConfig one = o.machine;  // as the baseline runs: one node, no boundaries (rtsim_cli.cpp)
        one.dims = {1, 1, 1};
        one.balance.policy = "none";
        j.baseline = frameBytes(binningSize(scene, one), one);
    }
    return j;
}

void checkJobMemory(const RtsimOptions& o, const Scene& scene, const MemoryLimits& limits) {
    const JobMemory j = jobMemory(o, scene);
    std::string what = (o.scene.file.empty() ? std::string("the scene") : "--scene " + o.scene.file) + ": its " +
                       std::to_string(scene.objects.size()) + " objects binned into the " +
                       std::to_string(o.machine.nodeCount()) + " nodes' grids (with the nodes themselves and the image";
    if (j.largestGrid > double(UniformGrid::kMaxReferences))
        throw SceneError(what + "): a grid of " + std::to_string(uint64_t(j.largestGrid)) +
                         " references (objects listed in cells), more than a grid holds (2^32 - 1)");
    if (j.comparison > 0 || j.baseline > 0) what += ", and beside it the reference runs' two processes; --no-baseline skips them";
    refuseIfTooBig(what + ")", j.together(), j.perProcess(), limits);
    msg::info("the nodes' grids at the frame's start: about " + std::to_string(int(j.grids / (1 << 20))) +
              " MiB; the job's memory: about " + std::to_string(int(j.frame / (1 << 20))) + " MiB a frame" +
              (j.together() > j.frame ? ", " + std::to_string(int(j.together() / (1 << 20))) + " MiB with its reference runs" : ""));
}

}  // namespace rt
