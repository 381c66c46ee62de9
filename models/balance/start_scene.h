// What the host knows of a frame before it starts, built once for the
// choices made then (--start-mix auto's links, start_links.h; --sample-end
// auto's view, sample_end.h): the world, its uniform cuts, the columns, the
// camera at the image size cfg gives (or the scene's), and the objects
// binned; and from them which node generates each primary ray at the
// planes a configuration starts from.
#pragma once
#include "balance/initial_split.h"
#include "base/mesh_geometry.h"
#include "camera.h"
#include "config/machine_config.h"
#include "region.h"
#include "scene.h"

namespace rt {

struct StartScene {
    StartScene(const MachineConfig& cfg, const Scene& scene);
    Box world;
    Lattice cuts;
    ColumnGeometry columns;
    Camera camera;
    ObjectBins bins;  // (of scene.objects, which must outlive it)
    // Each node's primary rays, its column's planes where `cfg` starts them (initialPlanes).
    PrimaryRays primaryRays(const MachineConfig& cfg) const;
};

}  // namespace rt
