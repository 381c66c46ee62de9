// A balancing policy: where a boundary between two column neighbours goes,
// decided from what both measured over the same round (doc/balancing.md).
// A policy is a pure function of one node's view, so each is tested on its
// own (tb/tests/test_policies.cpp); the protocol around it (rounds, reports,
// the guard, the slab handover) is models/balance/balance_agent.h.
//
// A new policy is one file (a class derived from BalancePolicy and its
// maker), and the maker's declaration and one entry in
// config/policy_table.cpp.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "box.h"
#include "config/machine_config.h"
#include "config/policy_table.h"

namespace rt {

// What a node measured over one round's span (since its last report to that
// neighbour), as it reports it.
struct LoadSample {
    Picos end = 0;              // the end of the span, by the reporter's clock
    Picos busy = 0, wait = 0;   // over the span
    Picos backlog = 0;          // work waiting at the end: rays in hand or arrived, primaries still to generate,
                                // times the span's mean step cost
    double sum = 0;             // the column's demand from its far end up to and including the reporter
                                // (to the upper neighbour: from the lowest node; to the lower: from the highest)
    double load() const { return busy + wait ? double(busy) / double(busy + wait) : 0.0; }  // the paper's load
    double demand() const { return double(busy) + double(backlog); }  // work of the span and work waiting
};

// Work along the progress axis, in fixed bins over the world's extent, so it
// stays valid when the box's faces move.
struct WorkProfile {
    double lo = 0, hi = 1;       // the world along the axis
    std::vector<double> bins;    // work (ps) per bin
    double binWidth() const { return (hi - lo) / double(bins.size()); }
    void add(double where, double work);
    // Work recorded in [a, b] (a part bin counts in proportion).
    double within(double a, double b) const;
    // The coordinate c such that [c, from] (upper) or [from, c] (lower)
    // holds `work` of the profile, going from `from` towards `limit`;
    // `limit` if the profile between holds less. With no work recorded, the
    // work is taken as spread evenly over [from, limit] with density `even`.
    double cut(double from, double limit, double work, double even) const;
    void clear() { std::fill(bins.begin(), bins.end(), 0.0); }
};

struct SlideQuery {
    Box own;                    // this node's box now
    int axis = 0;
    bool upper = true;          // the boundary is the box's upper face along the axis (else its lower)
    LoadSample mine, theirs;    // this round's samples: this node's (as sent) and its neighbour's
    const WorkProfile* profile = nullptr;  // this node's work over the span
    int index = 0, count = 1;   // this node's place along its column, and the column's length
    double minThickness = 0;    // absolute
};

class BalancePolicy {
public:
    virtual ~BalancePolicy() = default;
    // The boundary's new coordinate if this node gives a slab across it
    // now; nullopt if not. Both neighbours decide from the same two samples,
    // and at most one of them may give. The result must leave the box at
    // least minThickness thick (clampGive does).
    virtual std::optional<double> decide(const BalanceConfig& cfg, const SlideQuery& q) const = 0;
    // The guard counts a slab with no recorded work by its thickness, so
    // that empty slabs pass work on down the column (`relay`).
    virtual bool relays() const { return false; }
};

// The boundary moved into the box by `delta`, kept at least minThickness
// from the other face; nullopt if nothing is left to give.
std::optional<double> clampGive(const SlideQuery& q, double delta);


}  // namespace rt
