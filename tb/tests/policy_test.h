// Helpers of the balancing protocol's unit tests (test_policies.cpp,
// test_agent.cpp, test_channel.cpp, test_between_frames.cpp): values a
// test builds by hand.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "balance/policy.h"
#include "balance/work_by_position.h"

namespace rt::test {

inline constexpr Picos us = 1000000;

inline SlideQuery query(double ownLoad, double otherLoad, bool upper = true) {
    SlideQuery q;
    q.own = Box{Vec3(0.0), Vec3(1.0)};
    q.axis = 0;
    q.upper = upper;
    q.mine.busy = Picos(ownLoad * 1000);
    q.mine.wait = 1000 - q.mine.busy;
    q.theirs.busy = Picos(otherLoad * 1000);
    q.theirs.wait = 1000 - q.theirs.busy;
    q.minThickness = 0.1;
    return q;
}

inline BalanceConfig config(const std::string& p, double gain = 0.5) {
    BalanceConfig b;
    b.policy = p;
    b.gain = gain;
    b.deadband = 0.05;
    return b;
}

inline std::optional<double> decide(const BalanceConfig& b, const SlideQuery& q) { return findPolicy(b.policy)->make()->decide(b, q); }

inline WorkProfile profile(std::vector<double> bins) {
    WorkProfile p;
    p.lo = 0;
    p.hi = 1;
    p.bins = std::move(bins);
    return p;
}

}  // namespace rt::test
