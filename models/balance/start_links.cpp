#include "balance/start_links.h"

#include <algorithm>
#include <cstdio>

#include "balance/initial_split.h"
#include "balance/start_scene.h"

namespace rt {

namespace {

// The most primary rays any one node generates, its column's planes at `mix`.
size_t busiestBoxRays(MachineConfig cfg, double mix, const StartScene& at) {
    if (mix == 0) cfg.balance.startAligned = cfg.balance.startLighterOnly = false;
    cfg.balance.startMix = mix;
    size_t most = 0;
    for (const auto& pixels : at.primaryRays(cfg).perNode) most = std::max(most, pixels.size());
    return most;
}

}  // namespace

void weighStartLinks(MachineConfig& cfg, const Scene& scene) {
    BalanceConfig& b = cfg.balance;
    if (b.policy != "sample" || b.startMix != 0.5 || b.startMixWhy.rfind("auto", 0) != 0 || !cfg.startBoundaries.empty())
        return;  // (only the half start auto chose)
    const StartScene at(cfg, scene);
    const size_t half = busiestBoxRays(cfg, 0.5, at), uniform = busiestBoxRays(cfg, 0, at);
    const TestAgainstHop t = testAgainstHop(cfg, scene.objects);
    const double work = t.handling + kTestsPerRayInHeaviestBox * t.test;  // ps a ray in the heaviest box
    if (!(double(half) * t.wire > kLinkOverUniformFrame * double(uniform) * std::max(t.wire, work))) return;
    char why[400];
    std::snprintf(why, sizeof why,
                  "auto: half by the objects, half by the length would give one box %zu primary rays (the uniform "
                  "split's busiest: %zu), and at %.3g ns each on its link (a ray's work in the heaviest box: %.3g ns, "
                  "its handling and %d tests) that link would take over %g times the uniform split's frame: the "
                  "uniform split",
                  half, uniform, t.wire / 1000, work / 1000, kTestsPerRayInHeaviestBox, kLinkOverUniformFrame);
    b.startMix = 0;
    b.startAligned = b.startLighterOnly = false;
    b.startGeneration = 0;
    b.startMixWhy = why;
}

}  // namespace rt
