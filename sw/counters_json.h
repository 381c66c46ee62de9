// Counters as JSON, the same keys in rtref's stats and rtsim's report.
#pragma once
#include <nlohmann/json.hpp>

#include "counters.h"

namespace rt {

inline nlohmann::json countersJson(const Counters& c) {
    nlohmann::json j;
    j["primary_rays"] = c.primaryRays;
    j["primary_hits"] = c.primaryHits;
    j["shadow_rays"] = c.shadowRays;
    j["shadow_hits"] = c.shadowHits;
    j["secondary_rays"] = c.secondaryRays;
    j["secondary_hits"] = c.secondaryHits;
    j["intersection_tests"] = c.intersectionTests();
    for (int k = 0; k < kPrimitiveKinds; ++k)
        j["intersection_tests_by_primitive"][primitiveName(PrimitiveKind(k))] = c.tests[k];
    j["voxel_steps"] = c.voxelSteps;
    j["shadings"] = c.shadings;
    j["contributions"] = c.contributions;
    return j;
}

}  // namespace rt
