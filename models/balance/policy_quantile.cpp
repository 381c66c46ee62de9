// `quantile`: every boundary goes to its quantile of the column's demand.
//
// A node's demand over a round is the work it did plus the work waiting in
// it (rays in hand or arrived, primaries still to generate, at the round's
// mean cost per step): unlike the paper's load, it keeps growing with the
// backlog once a node is saturated. Reports carry running sums along the
// column: to the upper neighbour the demand of the nodes from the lowest up
// to the reporter (P), to the lower one from the highest down (S). The
// boundary between nodes k and k + 1 (of a column of n) belongs at the
// point where the demand below it is (k + 1) / n of the column's,
// T = P + S; both nodes see the same P and S, so both know which of them
// holds the excess, and only that one gives: gain x the excess, cut from its
// work profile next to the boundary.
//
// Stability (doc/balancing.md): with gain g <= 1 each round moves a
// boundary a fraction g of the way to its target as last measured, never
// past it, so a fixed target is approached geometrically, without
// overshoot; the dead band (a share of T / n) stops it when close. Targets
// move as sums travel (one hop per round), which the gain damps.
#include "balance/policy.h"

#include <algorithm>

namespace rt {
namespace {

class Quantile : public BalancePolicy {
public:
    std::optional<double> decide(const BalanceConfig& cfg, const SlideQuery& q) const override {
        const int k = q.upper ? q.index : q.index - 1;  // the boundary's lower node
        const double p = q.upper ? q.mine.sum : q.theirs.sum, s = q.upper ? q.theirs.sum : q.mine.sum;
        const double total = p + s;
        if (!(total > 0)) return std::nullopt;
        const double target = total * double(k + 1) / double(q.count);
        const double excess = q.upper ? p - target : target - p;  // what this side holds beyond the target
        if (!(excess > cfg.deadband * total / double(q.count))) return std::nullopt;
        const double demand = q.mine.demand();
        if (!(demand > 0)) return std::nullopt;
        const double shed = cfg.gainOf() * std::min(excess, demand);
        const double lo = q.own.lo[q.axis], hi = q.own.hi[q.axis];
        const double face = q.upper ? hi : lo, limit = q.upper ? lo : hi;
        // The profile gives the demand's shape in the box: cut where its share is shed / demand.
        const double recorded = q.profile ? q.profile->within(lo, hi) : 0.0;
        const double c = recorded > 0 ? q.profile->cut(face, limit, shed / demand * recorded, 0.0)
                                      : face + (q.upper ? -1 : 1) * (hi - lo) * shed / demand;
        return clampGive(q, q.upper ? face - c : c - face);
    }
};

}  // namespace

std::unique_ptr<BalancePolicy> makeQuantilePolicy() { return std::make_unique<Quantile>(); }

}  // namespace rt
