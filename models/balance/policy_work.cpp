// `work`: the heavier node (by the paper's load, beyond the dead band) sheds
// gain x half the busy-time gap of the round, taking it from the work it
// recorded next to the boundary.
#include "balance/policy.h"

namespace rt {
namespace {

class Work : public BalancePolicy {
public:
    std::optional<double> decide(const BalanceConfig& cfg, const SlideQuery& q) const override {
        if (!(q.mine.load() - q.theirs.load() > cfg.deadband)) return std::nullopt;
        if (q.mine.busy <= q.theirs.busy || !q.profile) return std::nullopt;
        const double shed = cfg.gainOf() * 0.5 * double(q.mine.busy - q.theirs.busy);
        const double lo = q.own.lo[q.axis], hi = q.own.hi[q.axis];
        const double face = q.upper ? hi : lo, limit = q.upper ? lo : hi;
        const double c = q.profile->cut(face, limit, shed, double(q.mine.busy) / (hi - lo));
        return clampGive(q, q.upper ? face - c : c - face);
    }
};

}  // namespace

std::unique_ptr<BalancePolicy> makeWorkPolicy() { return std::make_unique<Work>(); }

}  // namespace rt
