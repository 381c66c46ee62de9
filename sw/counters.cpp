#include "counters.h"

namespace rt {

Counters& Counters::operator+=(const Counters& o) {
    primaryRays += o.primaryRays;
    primaryHits += o.primaryHits;
    shadowRays += o.shadowRays;
    shadowHits += o.shadowHits;
    secondaryRays += o.secondaryRays;
    secondaryHits += o.secondaryHits;
    for (int k = 0; k < kPrimitiveKinds; ++k) tests[k] += o.tests[k];
    voxelSteps += o.voxelSteps;
    shadings += o.shadings;
    contributions += o.contributions;
    return *this;
}

}  // namespace rt
