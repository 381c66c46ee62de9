// The balancing policies on their own: each policy's decisions and the work
// profile they cut from, against values worked out by hand (no machine run).
// The agent: test_agent.cpp; links and their queues: test_channel.cpp;
// between frames: test_between_frames.cpp (one program, test_policies).
#include <algorithm>
#include <set>
#include <string>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "balance/balance_agent.h"
#include "base/fifo.h"
#include "balance/frame_forecast.h"
#include "channel/link.h"
#include "balance/minimax_split.h"
#include "balance/policy.h"
#include "balance/between_frames.h"
#include "balance/move_forecast.h"
#include "balance/sample_split.h"
#include "balance/work_by_position.h"

#include "policy_test.h"

using namespace rt;
using namespace rt::test;

TEST(Registry, EveryPolicyHasANameAndDynamicOnesAMaker) {
    for (const PolicyInfo& p : policies()) {
        EXPECT_EQ(findPolicy(p.name), &p);
        EXPECT_EQ(p.kind == PolicyKind::Dynamic, p.make != nullptr) << p.name;
    }
    EXPECT_EQ(findPolicy("nonsense"), nullptr);
    EXPECT_TRUE(config("quantile").dynamic());
    EXPECT_FALSE(config("median").dynamic());
    BalanceConfig b = config("quantile", 0);
    EXPECT_EQ(b.gainOf(), 0.5);  // the policy's default
}

TEST(Registry, ResplitsHelpStatesTheGainAMoveMustForecast) {
    // --help and doc/usage.md quote the margin; it is kMinForecastGain's.
    const std::string said = std::to_string(int(std::lround(kMinForecastGain * 100))) + " % faster";
    EXPECT_NE(std::string(findPolicy("resplit")->help).find(said), std::string::npos) << findPolicy("resplit")->help;
}

TEST(WorkProfile, WithinAndCutByHand) {
    const WorkProfile p = profile({0, 0, 0, 0, 0, 0, 0, 100, 100, 800});  // bins of 0.1
    EXPECT_NEAR(p.within(0.0, 1.0), 1000, 1e-9);
    EXPECT_NEAR(p.within(0.85, 1.0), 50 + 800, 1e-9);  // half of bin 8, all of bin 9
    EXPECT_NEAR(p.cut(1.0, 0.0, 400, 0), 0.95, 1e-12);  // from the top: half of the top bin
    EXPECT_NEAR(p.cut(1.0, 0.0, 850, 0), 0.85, 1e-12);  // the top bin and half the next
    EXPECT_NEAR(p.cut(0.0, 1.0, 250, 0), 0.9 + 0.1 * 50.0 / 800, 1e-12);  // from the bottom: 200 by 0.9, then 50 of 800
    EXPECT_NEAR(p.cut(0.0, 0.5, 10, 0), 0.5, 1e-12);     // nothing recorded up to the limit: the limit
    EXPECT_NEAR(profile({0, 0}).cut(0.2, 1.0, 30, 100), 0.5, 1e-12);  // none at all: spread evenly (density 100)
}

TEST(Slide, DeadBandAndOnlyTheHeavierGives) {
    const BalanceConfig b = config("slide");
    EXPECT_FALSE(decide(b, query(0.54, 0.5)));  // inside the dead band
    EXPECT_FALSE(decide(b, query(0.5, 0.9)));   // lighter: never gives
    const auto x = decide(b, query(0.9, 0.5));
    ASSERT_TRUE(x);
    EXPECT_NEAR(*x, 1.0 - 0.5 * 0.4 * 1.0, 1e-12);  // upper face moves down by gain x difference x thickness
    const auto y = decide(b, query(0.9, 0.5, false));
    ASSERT_TRUE(y);
    EXPECT_NEAR(*y, 0.2, 1e-12);  // lower face moves up
}

TEST(Slide, NeverBelowMinimumThicknessEvenAfterGivingOnTheOtherSide) {
    const BalanceConfig b = config("slide", 10.0);  // a huge step
    SlideQuery q = query(1.0, 0.0);
    const auto x = decide(b, q);
    ASSERT_TRUE(x);
    EXPECT_NEAR(*x, 0.1, 1e-12);  // clamped: exactly the minimum is left
    q.own.hi.x = *x;  // the box already gave that much on its upper side
    q.upper = false;
    EXPECT_FALSE(decide(b, q));  // nothing left to give on the lower side
}

// `relay` takes the load as demand: two nodes busy all the round (the
// paper's loads 1 and 1, inside any dead band) still differ when one has
// 60 of work waiting and the other none: (80 - 20) / (80 + 20) = 0.6.
TEST(Relay, DemandDoesNotSaturateAndOnlyTheHeavierGives) {
    const BalanceConfig b = config("relay");
    SlideQuery q = query(1.0, 1.0);
    EXPECT_FALSE(decide(config("slide"), q));
    EXPECT_FALSE(decide(b, q));  // no backlog on either side: equal
    q.mine.busy = q.theirs.busy = 20;
    q.mine.wait = q.theirs.wait = 0;
    q.mine.backlog = 60;
    const auto x = decide(b, q);
    ASSERT_TRUE(x);
    EXPECT_NEAR(*x, 1.0 - 0.5 * 0.6 * 1.0, 1e-12);  // gain x relative demand difference x thickness
    std::swap(q.mine, q.theirs);
    EXPECT_FALSE(decide(b, q));  // the lighter never gives
    q.mine.backlog = 2;
    q.theirs.backlog = 0;
    EXPECT_FALSE(decide(b, q));  // 22 against 20: 0.048, inside the dead band of 0.05
    EXPECT_TRUE(findPolicy("relay")->make()->relays());
    EXPECT_FALSE(findPolicy("slide")->make()->relays());
}

TEST(Work, ShedsFromTheWorkNextToTheBoundary) {
    const BalanceConfig b = config("work", 1.0);
    SlideQuery q = query(1.0, 0.2);
    const WorkProfile p = profile({0, 0, 0, 0, 0, 0, 0, 100, 100, 800});
    q.profile = &p;  // busy 1000 against 200: shed (1000 - 200) / 2 = 400, half of the top bin
    const auto x = decide(b, q);
    ASSERT_TRUE(x);
    EXPECT_NEAR(*x, 0.95, 1e-12);
    q.upper = false;  // from the lower end: 200 by 0.9, then a quarter of the top bin: 0.925,
    const auto y = decide(b, q);  // more than the minimum thickness allows: clamped at 0.9
    ASSERT_TRUE(y);
    EXPECT_NEAR(*y, 0.9, 1e-12);
}

TEST(Quantile, ExactlyOneSideOfEachBoundaryGivesTowardsTheQuantile) {
    // A column of 3 with demands 600, 200, 100 (T = 900, T / 3 = 300). The
    // boundary between nodes 0 and 1 belongs where 300 lies below it: node 0
    // holds 300 too many and gives gain x 300 of its 600.
    const BalanceConfig b = config("quantile", 0.5);
    const WorkProfile even = profile({});
    SlideQuery q0;  // node 0, its upper face
    q0.own = Box{Vec3(0.0), Vec3(1.0, 1.0, 1.0)};
    q0.upper = true;
    q0.index = 0;
    q0.count = 3;
    q0.minThickness = 0.01;
    q0.mine.busy = 600;
    q0.mine.sum = 600;          // P: demand from the lowest node through node 0
    q0.theirs.busy = 200;
    q0.theirs.sum = 200 + 100;  // S: from the highest node through node 1
    const auto x = decide(b, q0);
    ASSERT_TRUE(x);
    EXPECT_NEAR(*x, 1.0 - 150.0 / 600.0, 1e-12);  // no profile: work taken as even over the box
    SlideQuery q1 = q0;  // node 1, its lower face: the same two sums, the other way round
    q1.upper = false;
    q1.index = 1;
    q1.own = Box{Vec3(1.0, 0.0, 0.0), Vec3(2.0, 1.0, 1.0)};
    std::swap(q1.mine, q1.theirs);
    EXPECT_FALSE(decide(b, q1));
    // Between nodes 1 and 2 (below: 800 of 900, target 600): node 1 holds 200 too many.
    SlideQuery q2 = q1;
    q2.upper = true;
    q2.mine = LoadSample{0, 200, 0, 0, 800};
    q2.theirs = LoadSample{0, 100, 0, 0, 100};
    const auto z = decide(b, q2);
    ASSERT_TRUE(z);
    EXPECT_NEAR(*z, 2.0 - 0.5, 1e-12);  // gain 0.5 x 200 = 100 of its 200: half the box
    q2.mine.sum = 650;  // within the dead band (0.05 x 750 / 3) of its target 500? no: 150 over. Closer:
    q2.mine.sum = 510;
    q2.theirs.sum = 250;  // T 760, target 506.7: 3.3 over, inside the dead band of 12.7
    EXPECT_FALSE(decide(b, q2));
    (void)even;
}

// ---- --faces ideal-layer (models/balance/ideal_layer_faces.h) ----

TEST(IdealLayerFaces, SlideRuleOnTheLayersSummedLoadsByHand) {
    // Layers [0,1] [1,2] [2,3]; gain 0.25, dead band 0.05, minimum 0.05.
    IdealLayerFaces f({1.0, 2.0}, 0.0, 3.0, 0.05, 0.25, 0.05);
    // Interval 0: layer 0 at 0.9; layer 1's two nodes 10/50 and 30/50, so
    // 40 of 100: 0.4 (not their loads' mean); layer 2 at 0.5.
    f.add(0, 0, 90, 10);
    f.add(1, 0, 10, 40);
    f.add(1, 0, 30, 20);
    f.add(2, 0, 50, 50);
    EXPECT_EQ(f.face(0, 0), 1.0);
    EXPECT_EQ(f.face(1, 0), 2.0);
    // Face 0 moves into layer 0 by 0.25 x 0.5 x 1; face 1 into layer 2 by
    // 0.25 x 0.1 x 1 (layer 2's thickness, 3 - 2).
    EXPECT_NEAR(f.face(0, 1), 0.875, 1e-12);
    EXPECT_NEAR(f.face(1, 1), 2.025, 1e-12);
    // Fixed once asked for: loads added later for interval 0 change nothing.
    f.add(2, 0, 1000, 0);
    EXPECT_NEAR(f.face(1, 1), 2.025, 1e-12);
    // Interval 1: no loads (0 = 0) keep the planes; interval 2: layer 1 at
    // 1.0 and layer 0 idle: face 0 moves up into layer 1 by
    // 0.25 x 1 x (2.025 - 0.875), face 1 down by 0.25 x 1 x the thickness
    // layer 1 has after face 0's move (the faces are judged in order).
    f.add(1, 2, 100, 0);
    f.add(0, 2, 0, 100);
    f.add(2, 2, 0, 100);
    EXPECT_NEAR(f.face(0, 2), 0.875, 1e-12);
    const double f0 = 0.875 + 0.25 * (2.025 - 0.875);
    EXPECT_NEAR(f.face(0, 3), f0, 1e-12);
    EXPECT_NEAR(f.face(1, 3), 2.025 - 0.25 * (2.025 - f0), 1e-12);
    // A step past the layer's minimum stops at it.
    IdealLayerFaces g({1.0}, 0.0, 2.0, 0.05, 4.0, 0.3);
    g.add(0, 0, 100, 0);
    EXPECT_NEAR(g.face(0, 1), 0.3, 1e-12);
    EXPECT_THROW(g.face(1, 1), std::logic_error);
}
