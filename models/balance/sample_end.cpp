#include "balance/sample_end.h"

#include "balance/initial_split.h"
#include "balance/sample_split.h"
#include "base/mesh_geometry.h"
#include "camera.h"
#include "region.h"

namespace rt {

bool onlyTopNodesGenerateSample(const MachineConfig& cfg, const Scene& scene) {
    const Box world = scene.worldBox();
    const Lattice cuts = Lattice::uniform(world, cfg.dims);
    const ColumnGeometry g(cfg.balance.axis, cfg.dims);
    if (g.length() < 2) return false;  // (the top node is the lowest)
    const int width = cfg.width ? cfg.width : scene.view.width, height = cfg.height ? cfg.height : scene.view.height;
    const Camera camera(scene.view, width, height);
    const ObjectBins bins(scene.objects, cuts, roundingMargin(world));
    const ColumnPlanes planes = initialPlanes(cfg, cuts, world, bins, minThicknessOf(cfg, world), &camera);
    const PrimaryRays rays = assignPrimaryRays(camera, world, cuts, g, planes, cfg.pixelStride);
    for (size_t i = 0; i < rays.perNode.size(); ++i) {
        if (cellAt(i, cfg.dims)[g.axis] == g.length() - 1) continue;
        for (uint32_t p : rays.perNode[i])
            if (inSample(p, uint32_t(width))) return false;
    }
    return true;
}

void chooseSampleEnd(MachineConfig& cfg, const Scene& scene) {
    BalanceConfig& b = cfg.balance;
    if (!b.sampleEndAuto || b.policy != "sample" || !cfg.startBoundaries.empty()) return;
    const TestAgainstHop t = testAgainstHop(cfg, scene.objects);
    b.sampleCredit = t.testsAreTheWork;
    b.sampleEndWhy = "auto: " + t.costs + (t.testsAreTheWork ? ": credit" : ": generated");
    if (b.sampleCredit || !onlyTopNodesGenerateSample(cfg, scene)) return;
    b.sampleCredit = true;
    b.sampleEndWhy = "auto: " + t.costs + ", but only the columns' top nodes generate primary rays of the sample, "
                     "and a gather on generating would climb before they come down: credit";
}

}  // namespace rt
