#include "balance/start_scene.h"

namespace rt {

namespace {
int widthOf(const MachineConfig& cfg, const Scene& scene) { return cfg.width ? cfg.width : scene.view.width; }
int heightOf(const MachineConfig& cfg, const Scene& scene) { return cfg.height ? cfg.height : scene.view.height; }
}  // namespace

StartScene::StartScene(const MachineConfig& cfg, const Scene& scene)
    : world(scene.worldBox()),
      cuts(Lattice::uniform(world, cfg.dims)),
      columns(cfg.balance.axis, cfg.dims),
      camera(scene.view, widthOf(cfg, scene), heightOf(cfg, scene)),
      bins(scene.objects, cuts, roundingMargin(world)) {}

PrimaryRays StartScene::primaryRays(const MachineConfig& cfg) const {
    const ColumnPlanes planes = initialPlanes(cfg, cuts, world, bins, minThicknessOf(cfg, world), &camera);
    return assignPrimaryRays(camera, world, cuts, columns, planes, cfg.pixelStride);
}

}  // namespace rt
