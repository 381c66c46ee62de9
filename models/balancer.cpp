#include "balancer.h"

#include <algorithm>

namespace rt {

std::optional<double> decideSlide(const BalanceConfig& cfg, const SlideQuery& q) {
    if (!(q.ownLoad - q.otherLoad > cfg.deadband)) return std::nullopt;  // the lighter side never gives
    const double lo = q.own.lo[q.axis], hi = q.own.hi[q.axis];
    const double thickness = hi - lo;
    const double room = thickness - q.minThickness;  // the most it may give
    if (!(room > 0)) return std::nullopt;
    double delta = 0;
    if (cfg.policy == Policy::Slide) {
        // The paper: a step proportional to the load difference.
        delta = cfg.gain * (q.ownLoad - q.otherLoad) * thickness;
    } else if (cfg.policy == Policy::Work) {
        // Shed a share of the busy-time gap, from the bins next to the boundary.
        if (q.ownBusy <= q.otherBusy || q.histogram.empty()) return std::nullopt;
        double shed = cfg.gain * 0.5 * double(q.ownBusy - q.otherBusy);
        const size_t n = q.histogram.size();
        const double bin = thickness / double(n);
        for (size_t k = 0; k < n && shed > 0; ++k) {
            const double w = double(q.histogram[q.upper ? n - 1 - k : k]);
            if (w >= shed) {
                delta += bin * (shed / w);
                shed = 0;
            } else {
                delta += bin;
                shed -= w;
            }
        }
    } else {
        return std::nullopt;
    }
    delta = std::min(delta, room);
    if (!(delta > 1e-9 * thickness)) return std::nullopt;
    return q.upper ? hi - delta : lo + delta;
}

}  // namespace rt
