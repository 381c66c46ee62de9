// `slide`: the paper's rule. The heavier node (load = busy / (busy + wait)
// over the round) moves its face into itself by gain x the load difference x
// its thickness, if the loads differ by more than the dead band.
#include "balance/policy.h"

namespace rt {
namespace {

class Slide : public BalancePolicy {
public:
    std::optional<double> decide(const BalanceConfig& cfg, const SlideQuery& q) const override {
        const double diff = q.mine.load() - q.theirs.load();
        if (!(diff > cfg.deadband)) return std::nullopt;  // the lighter side never gives
        return clampGive(q, cfg.gainOf() * diff * (q.own.hi[q.axis] - q.own.lo[q.axis]));
    }
};

}  // namespace

std::unique_ptr<BalancePolicy> makeSlidePolicy() { return std::make_unique<Slide>(); }

}  // namespace rt
