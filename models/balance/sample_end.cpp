#include "balance/sample_end.h"

#include "balance/initial_split.h"
#include "balance/sample_split.h"
#include "balance/start_scene.h"
#include "base/mesh_geometry.h"

namespace rt {

bool onlyTopNodesGenerateSample(const MachineConfig& cfg, const Scene& scene) {
    const ColumnGeometry g(cfg.balance.axis, cfg.dims);
    if (g.length() < 2) return false;  // (the top node is the lowest)
    const StartScene at(cfg, scene);
    const uint32_t width = uint32_t(at.camera.width());
    const PrimaryRays rays = at.primaryRays(cfg);
    for (size_t i = 0; i < rays.perNode.size(); ++i) {
        if (cellAt(i, cfg.dims)[g.axis] == g.length() - 1) continue;
        for (uint32_t p : rays.perNode[i])
            if (inSample(p, width)) return false;
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
