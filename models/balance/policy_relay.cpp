// `relay`: the paper's rule under a reading that lets work travel down a
// column (doc/balancing.md, "Where slide's frame goes"). Two changes to
// `slide`, both of which the paper's text allows:
// - the load does not saturate: a node's load is its demand (work done and
//   waiting, LoadSample::demand), and the difference is taken relative to
//   the pair's, (mine - theirs) / (mine + theirs), so two busy nodes still
//   differ while one of them holds the column's unstarted work;
// - a slab may pass on what the giver was given: a slab whose part of the
//   box holds no recorded work counts by its thickness in the guard
//   (BalancePolicy::relays), as a box with no record does. Under `slide`
//   such a slab returns nothing, so the guard refuses it and the boxes past
//   the second never get work.
#include "balance/policy.h"

namespace rt {
namespace {

class Relay : public BalancePolicy {
public:
    std::optional<double> decide(const BalanceConfig& cfg, const SlideQuery& q) const override {
        const double mine = q.mine.demand(), theirs = q.theirs.demand();
        if (!(mine + theirs > 0)) return std::nullopt;
        const double diff = (mine - theirs) / (mine + theirs);
        if (!(diff > cfg.deadband)) return std::nullopt;  // the lighter side never gives
        return clampGive(q, cfg.gainOf() * diff * (q.own.hi[q.axis] - q.own.lo[q.axis]));
    }
    bool relays() const override { return true; }
};

}  // namespace

std::unique_ptr<BalancePolicy> makeRelayPolicy() { return std::make_unique<Relay>(); }

}  // namespace rt
