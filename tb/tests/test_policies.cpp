// The balancing protocol on its own: each policy's decisions, the work
// profile they cut from, the agent's rounds in lockstep with a neighbour,
// the guard, and the links' control lane, all against values worked out by
// hand in the tests (no machine run).
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

using namespace rt;

namespace {

constexpr Picos us = 1000000;

SlideQuery query(double ownLoad, double otherLoad, bool upper = true) {
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

BalanceConfig config(const std::string& p, double gain = 0.5) {
    BalanceConfig b;
    b.policy = p;
    b.gain = gain;
    b.deadband = 0.05;
    return b;
}

std::optional<double> decide(const BalanceConfig& b, const SlideQuery& q) { return findPolicy(b.policy)->make()->decide(b, q); }

WorkProfile profile(std::vector<double> bins) {
    WorkProfile p;
    p.lo = 0;
    p.hi = 1;
    p.bins = std::move(bins);
    return p;
}

}  // namespace

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

// ---- The agent: rounds, lockstep, ages, the guard ----

namespace {

struct FakeHost : BalanceHost {
    Box b{Vec3(0.0), Vec3(1.0)};
    std::vector<std::pair<int, Message>> reports;
    std::vector<std::pair<int, double>> slabs;
    Picos cost = 0, hop = 0, reportWire = 0, occupied = 0, rayTime = 0;
    const Box& box() const override { return b; }
    void sendReport(int side, Message m) override { reports.push_back({side, std::move(m)}); }
    void giveSlab(int side, double boundary) override {  // the box shrinks along x, as a node's does
        slabs.push_back({side, boundary});
        (side > 0 ? b.hi : b.lo)[0] = boundary;
    }
    Picos slabCost(int, double) const override { return cost; }
    Picos hopTime(int) const override { return hop; }
    Picos reportTime(int) const override { return reportWire; }
    Picos linkOccupied(int) const override { return occupied; }
    Picos rayOccupies(int) const override { return rayTime; }
    std::vector<std::pair<int, Message>> sent;  // sendOn: (direction, message)
    int begun = 0;                              // sampleBegins calls
    void sendOn(int dir, Message m) override { sent.push_back({dir, std::move(m)}); }
    void sampleBegins() override { ++begun; }
};

// Takes every action the agent has due, as a node does between its steps.
void settle(BalanceAgent& a) {
    while (a.pending()) a.act();
}

BalanceConfig agentConfig() {
    BalanceConfig b = config("slide", 0.25);
    b.interval = 20 * us;
    return b;
}

// One round between node 0 of a column of two (busy all of its 20 us, its
// one 1 us step at `where`) and node 1 (idle all of it): node 0 decides at
// `decideAt` on node 1's report. Its slabs are in ha.slabs.
BalanceStats oneRound(const BalanceConfig& cfg, FakeHost& ha, double where, Picos decideAt) {
    const Box world{Vec3(0.0), Vec3(2.0, 1.0, 1.0)};
    FakeHost hb;
    BalanceAgent a(cfg, ha, world, 0, 2, false, true, 0.05), b(cfg, hb, world, 1, 2, true, false, 0.05);
    a.recordStep(where, 1 * us);
    a.closeInterval(20 * us, 20 * us, 0, 0);
    settle(a);
    b.closeInterval(20 * us, 0, 20 * us, 0);
    settle(b);
    a.onReport(+1, hb.reports[0].second, decideAt);
    settle(a);
    return a.stats();
}

}  // namespace

TEST(Agent, OneRoundEachWayAndOnlyTheHeavierGives) {
    const BalanceConfig cfg = agentConfig();
    FakeHost ha, hb;
    hb.b = Box{Vec3(1.0, 0.0, 0.0), Vec3(2.0, 1.0, 1.0)};
    const Box world{Vec3(0.0), Vec3(2.0, 1.0, 1.0)};
    BalanceAgent a(cfg, ha, world, 0, 2, false, true, 0.05), b(cfg, hb, world, 1, 2, true, false, 0.05);
    for (int i = 0; i < 10; ++i) a.recordStep(0.5, 2 * us);  // 20 us of work in 10 steps
    a.closeInterval(20 * us, 20 * us, 0, 3);                  // busy the whole interval, 3 rays waiting
    settle(a);
    b.recordStep(1.5, 5 * us);
    b.closeInterval(20 * us, 7 * us, 13 * us, 0);  // 2 us of it handling messages: neither execution nor wait
    settle(b);
    ASSERT_EQ(ha.reports.size(), 1u);
    ASSERT_EQ(hb.reports.size(), 1u);
    EXPECT_EQ(ha.reports[0].first, +1);
    EXPECT_EQ(ha.reports[0].second.body().interval, 0);
    EXPECT_EQ(ha.reports[0].second.body().busy, 20 * us);
    EXPECT_EQ(ha.reports[0].second.body().backlog, 3 * 2 * us);  // 3 waiting at the mean step, 2 us
    EXPECT_EQ(hb.reports[0].second.body().busy, 5 * us);
    EXPECT_EQ(hb.reports[0].second.body().wait, 13 * us);
    a.onReport(+1, hb.reports[0].second, 21 * us);
    settle(a);
    b.onReport(-1, ha.reports[0].second, 21 * us);
    settle(b);
    ASSERT_EQ(ha.slabs.size(), 1u);  // loads 1.0 and 5 / 18: a gives 0.25 x (1 - 5 / 18) of its thickness
    EXPECT_NEAR(ha.slabs[0].second, 1.0 - 0.25 * (1 - 5.0 / 18), 1e-12);
    EXPECT_TRUE(hb.slabs.empty());
    EXPECT_EQ(a.stats().decisions, 1u);
    EXPECT_EQ(a.stats().ages.count(), 1u);
    EXPECT_EQ(a.stats().ages.max(), 51u);  // decided 1 us after the loads' end: 0.05 intervals, 51.2 / 1024
    EXPECT_THROW(a.onReport(+1, hb.reports[0].second, 22 * us), std::logic_error);  // round 0 again: out of lockstep
}

TEST(Agent, TakesOneHostCallPerActionLowerSideFirst) {
    // A node in the middle of a column reports to both sides when an
    // interval closes: one report per act(), so the node can let the kernel
    // catch up after each, as after any step.
    const BalanceConfig cfg = agentConfig();
    FakeHost h;
    const Box world{Vec3(0.0), Vec3(3.0, 1.0, 1.0)};
    h.b = Box{Vec3(1.0, 0.0, 0.0), Vec3(2.0, 1.0, 1.0)};
    BalanceAgent a(cfg, h, world, 1, 3, true, true, 0.05);
    a.closeInterval(20 * us, 20 * us, 0, 0);
    EXPECT_TRUE(h.reports.empty());  // nothing until acted on
    ASSERT_TRUE(a.pending());
    a.act();
    ASSERT_EQ(h.reports.size(), 1u);
    EXPECT_EQ(h.reports[0].first, -1);
    ASSERT_TRUE(a.pending());
    a.act();
    ASSERT_EQ(h.reports.size(), 2u);
    EXPECT_EQ(h.reports[1].first, +1);
    a.act();  // nothing more is due on either side
    EXPECT_FALSE(a.pending());
    // Start targets on both faces: one give per act(), the lower face first.
    BalanceConfig held = cfg;
    held.policy = "resplit";
    FakeHost g;
    g.b = h.b;
    BalanceAgent b(held, g, world, 1, 3, true, true, 0.05);
    b.startAt(1.2, 1.8);
    EXPECT_TRUE(g.slabs.empty());
    b.act();
    ASSERT_EQ(g.slabs.size(), 1u);
    EXPECT_EQ(g.slabs[0], std::make_pair(-1, 1.2));
    b.act();
    ASSERT_EQ(g.slabs.size(), 2u);
    EXPECT_EQ(g.slabs[1], std::make_pair(+1, 1.8));
    EXPECT_FALSE(b.pending());
}

TEST(Agent, SlowReportsMakeLongerRoundsNotAQueue) {
    // The neighbour's report takes 3 intervals to arrive. Meanwhile a node
    // closes intervals but sends nothing (round 0 is not decided); once it
    // decides, its next report covers every interval closed since the last.
    const BalanceConfig cfg = agentConfig();
    FakeHost ha, hb;
    const Box world{Vec3(0.0), Vec3(2.0, 1.0, 1.0)};
    BalanceAgent a(cfg, ha, world, 0, 2, false, true, 0.05), b(cfg, hb, world, 1, 2, true, false, 0.05);
    const auto interval = [](BalanceAgent& n, Picos end, Picos traced, Picos busy, Picos wait) {
        n.recordStep(0.5, traced);
        n.closeInterval(end, busy, wait, 0);
        settle(n);
    };
    interval(a, 20 * us, 10 * us, 10 * us, 10 * us);
    interval(b, 20 * us, 10 * us, 10 * us, 10 * us);
    interval(a, 40 * us, 15 * us, 25 * us, 15 * us);
    interval(a, 60 * us, 15 * us, 40 * us, 20 * us);
    interval(a, 80 * us, 10 * us, 50 * us, 30 * us);
    EXPECT_EQ(ha.reports.size(), 1u);
    a.onReport(+1, hb.reports[0].second, 81 * us);
    settle(a);
    ASSERT_EQ(ha.reports.size(), 2u);
    const Message& r1 = ha.reports[1].second;
    EXPECT_EQ(r1.body().interval, 1);
    EXPECT_EQ(r1.body().busy, 40 * us);  // intervals 2 to 4: 15 + 15 + 10
    EXPECT_EQ(r1.body().wait, 20 * us);
    EXPECT_EQ(r1.body().end, 80 * us);
    EXPECT_EQ(a.stats().ages.max(), 3123u);  // round 0's loads ended at 20 us: 61 / 20 intervals, 3123.2 / 1024
}

TEST(Agent, ReportsArePacedToTheirShareOfTheLink) {
    // A report takes 1 us on the wire and may take 2 % of the link: one
    // report per 50 us, rounded up to whole intervals: a period of 60 us.
    // The neighbour answers at once, so only the pacing holds the reports
    // back: after the first (20 us), at the multiples of 60 us. A report
    // covers every interval since the last, and its loads are as fresh as
    // without pacing (decided 1 us after their end).
    BalanceConfig cfg = agentConfig();
    cfg.reportShare = 0.02;
    FakeHost ha, hb;
    ha.reportWire = hb.reportWire = 1 * us;
    const Box world{Vec3(0.0), Vec3(2.0, 1.0, 1.0)};
    BalanceAgent a(cfg, ha, world, 0, 2, false, true, 0.05), b(cfg, hb, world, 1, 2, true, false, 0.05);
    std::vector<Picos> sentAt;
    for (Picos k = 1; k <= 8; ++k) {
        const Picos end = k * 20 * us;
        a.recordStep(0.5, 5 * us);
        a.closeInterval(end, k * 5 * us, k * 15 * us, 0);
        settle(a);
        b.closeInterval(end, 0, k * 20 * us, 0);
        settle(b);
        if (ha.reports.size() > sentAt.size()) {
            sentAt.push_back(end);
            ASSERT_EQ(hb.reports.size(), ha.reports.size());
            a.onReport(+1, hb.reports.back().second, end + 1 * us);
            settle(a);
            b.onReport(-1, ha.reports.back().second, end + 1 * us);
            settle(b);
        }
    }
    EXPECT_EQ(sentAt, (std::vector<Picos>{20 * us, 60 * us, 120 * us}));
    ASSERT_EQ(ha.reports.size(), 3u);
    EXPECT_EQ(ha.reports[1].second.body().busy, 10 * us);  // intervals 2 and 3, 5 us traced in each
    EXPECT_EQ(ha.reports[1].second.body().wait, 30 * us);
    EXPECT_EQ(ha.reports[2].second.body().busy, 15 * us);  // intervals 4 to 6
    EXPECT_EQ(a.stats().decisions, 3u);
    EXPECT_EQ(a.stats().ages.max(), 51u);  // 1 us after the loads' end: 0.05 intervals
}

TEST(Agent, HandlingMessagesIsNoLoad) {
    // Busy the whole interval, but only passing rays on and handling
    // balancing messages: load 0, so nothing moves. (Counting that time as
    // load kept idle columns sliding slabs back and forth at the end of a
    // frame, with rays chasing them, and the frame never ended.)
    const BalanceConfig cfg = agentConfig();
    FakeHost ha, hb;
    const Box world{Vec3(0.0), Vec3(2.0, 1.0, 1.0)};
    BalanceAgent a(cfg, ha, world, 0, 2, false, true, 0.05), b(cfg, hb, world, 1, 2, true, false, 0.05);
    a.closeInterval(20 * us, 20 * us, 0, 0);
    settle(a);
    b.closeInterval(20 * us, 0, 20 * us, 0);
    settle(b);
    EXPECT_EQ(ha.reports[0].second.body().busy, 0);
    a.onReport(+1, hb.reports[0].second, 21 * us);
    settle(a);
    b.onReport(-1, ha.reports[0].second, 21 * us);
    settle(b);
    EXPECT_TRUE(ha.slabs.empty());
    EXPECT_TRUE(hb.slabs.empty());
    EXPECT_EQ(a.stats().intervals[0].busy, 20 * us);  // the node's own record keeps every busy picosecond
}

TEST(Agent, IntervalHistoryStaysBoundedAndKeepsEveryPicosecond) {
    // 3,000 intervals of 20 us, interval i busy i ps: at 1,024 records they
    // merge pairwise (512 records of 2), at 2,048 intervals again (512 of
    // 4), and the last 952 make 238 records of 4: 750 in all, the last
    // ending with the last interval, and the busy and wait totals kept.
    const BalanceConfig cfg = agentConfig();
    FakeHost h;
    const Box world{Vec3(0.0), Vec3(1.0)};
    BalanceAgent a(cfg, h, world, 0, 1, false, false, 0.05);  // no neighbours: it only records
    Picos busy = 0;
    for (Picos i = 1; i <= 3000; ++i) {
        busy += i;
        a.closeInterval(i * 20 * us, busy, i * 20 * us - busy, 0);
        settle(a);
    }
    const BalanceStats s = a.finalStats();
    EXPECT_EQ(s.intervalsPerRecord, 4u);
    ASSERT_EQ(s.intervals.size(), 750u);
    Picos sumBusy = 0, sumWait = 0;
    for (const IntervalRecord& r : s.intervals) {
        sumBusy += r.busy;
        sumWait += r.wait;
    }
    EXPECT_EQ(sumBusy, busy);
    EXPECT_EQ(sumBusy + sumWait, 3000 * 20 * us);
    EXPECT_EQ(s.intervals.back().end, 3000 * 20 * us);
    EXPECT_EQ(s.intervals[0].end, 4 * 20 * us);
    EXPECT_EQ(s.intervals[0].busy, Picos(1 + 2 + 3 + 4));
    // One more interval: a last, shorter record.
    a.closeInterval(3001 * 20 * us, busy + 7, 3001 * 20 * us - busy - 7, 0);
    settle(a);
    ASSERT_EQ(a.finalStats().intervals.size(), 751u);
    EXPECT_EQ(a.finalStats().intervals.back().busy, 7u);
}

// The links' queues: a ring that grows while it wraps round, turns into a
// list of chunks past one chunk's worth and back into a ring when it runs
// empty, and gives its memory back, must still hand out every item once, in
// order, and destroy each (an item owning memory shows a leak under the
// sanitizer build, a double destruction a crash). Small items stay in the
// ring (8,192 per chunk); 4 KiB items (16 per chunk) go through the chunks
// in nearly every burst.
struct SmallItem {
    std::unique_ptr<uint64_t> v;
};
struct LargeItem {
    std::unique_ptr<uint64_t> v;
    char pad[4088] = {};
};
template <class Item>
class FifoOf : public ::testing::Test {};
using FifoItems = ::testing::Types<SmallItem, LargeItem>;
TYPED_TEST_SUITE(FifoOf, FifoItems);

TYPED_TEST(FifoOf, KeepsOrderThroughWrapGrowthChunksAndReleaseLikeADeque) {
    using Item = TypeParam;
    static_assert(Fifo<LargeItem>::kChunk == 16 && Fifo<SmallItem>::kChunk == 8192);
    Fifo<Item> f;
    std::deque<uint64_t> ref;
    std::mt19937_64 rng(7);
    uint64_t next = 0;
    auto item = [](uint64_t v) {
        Item it{};
        it.v = std::make_unique<uint64_t>(v);
        return it;
    };
    for (int round = 0; round < 200; ++round) {
        // Bursts of different sizes, some drained to empty, some not.
        const int pushes = int(rng() % 300), pops = int(rng() % 320);
        for (int i = 0; i < pushes; ++i) {
            if (i % 2) f.push_back(item(next));
            else f.emplace_back(std::make_unique<uint64_t>(next));
            ref.push_back(next++);
        }
        ASSERT_EQ(f.size(), ref.size());
        for (size_t i = 0; i < ref.size(); i += 1 + ref.size() / 7) ASSERT_EQ(*f[i].v, ref[i]);
        if (!ref.empty()) {
            ASSERT_EQ(*f[ref.size() - 1].v, ref.back());
        }
        for (int i = 0; i < pops && !ref.empty(); ++i) {
            ASSERT_EQ(*f.front().v, ref.front());
            f.pop_front();
            ref.pop_front();
        }
        ASSERT_EQ(f.empty(), ref.empty());
    }
    Fifo<Item> g(std::move(f));  // moved whole, items left for its destructor
    EXPECT_EQ(g.size(), ref.size());
    EXPECT_TRUE(f.empty());
    f.push_back(item(1));  // a moved-from queue is an empty one
    EXPECT_EQ(*f.front().v, 1u);
}

TEST(Histogram, ExactForFewValuesThenWithinHalfABinAndBoundedByTheRange) {
    // Few distinct values: the percentiles are the values by rank.
    Histogram few;
    for (uint64_t v : {700, 100, 300, 300, 500, 900, 100, 300, 1000000, 300}) few.add(v);
    // sorted: 100 100 300 300 300 300 500 700 900 1000000
    EXPECT_EQ(few.percentile(0.0), 100.0);
    EXPECT_EQ(few.percentile(0.5), 300.0);  // rank 5
    EXPECT_EQ(few.percentile(0.65), 500.0);  // rank 6
    EXPECT_EQ(few.percentile(0.95), 1000000.0);  // rank 9
    EXPECT_EQ(few.max(), 1000000u);
    // 10^6 values spread over [1, 2^20): the percentiles of the sorted list
    // against the histogram's (within half a bin: 1/128), the bins it holds
    // (64 per octave, not 10^6), and two halves merged as one.
    std::vector<uint64_t> all;
    Histogram one, lo, hi;
    uint64_t x = 12345;
    for (int i = 0; i < 1000000; ++i) {
        x = x * 6364136223846793005ULL + 1442695040888963407ULL;  // (a fixed LCG: the same values every run)
        const uint64_t v = 1 + (x >> 44);
        all.push_back(v);
        one.add(v);
        (i % 2 ? hi : lo).add(v);
    }
    std::sort(all.begin(), all.end());
    lo.merge(hi);
    EXPECT_EQ(one.count(), all.size());
    EXPECT_EQ(lo.count(), all.size());
    EXPECT_LE(one.bins(), 20u * 64 + 64);
    EXPECT_EQ(one.max(), all.back());
    EXPECT_EQ(lo.max(), one.max());
    for (double p : {0.0, 0.01, 0.25, 0.5, 0.95, 0.999}) {
        SCOPED_TRACE(p);
        const double exact = double(all[size_t(p * double(all.size()))]);
        EXPECT_NEAR(one.percentile(p), exact, exact / 128 + 0.5);
        EXPECT_EQ(lo.percentile(p), one.percentile(p));
    }
    EXPECT_EQ(Histogram().percentile(0.5), 0.0);
}

// Single values wait in the histogram and go into its bins a few at a time,
// sorted: the figures must not depend on the order the values came in, nor
// on where the waiting ones stood when it was read, across the change from
// exact to coarse bins (at the 65th distinct value).
TEST(Histogram, TheOrderValuesComeInDoesNotMatter) {
    std::vector<uint64_t> values;
    for (uint64_t i = 0; i < 300; ++i) values.push_back(1000 + (i * 7919) % 97 * 13 + (i % 5 == 0 ? 100000 : 0));
    Histogram up, down, read;
    std::vector<uint64_t> sorted = values;
    std::sort(sorted.begin(), sorted.end());
    for (uint64_t v : sorted) up.add(v);
    for (auto it = values.rbegin(); it != values.rend(); ++it) down.add(*it);
    for (size_t i = 0; i < values.size(); ++i) {
        read.add(values[i]);
        if (i % 3 == 0) {
            EXPECT_EQ(read.count(), i + 1);  // counts the waiting ones
        }
        if (i == 40) read.percentile(0.5);   // settles the waiting ones (exact bins still)
        if (i == 150) read.merge(Histogram());  // and so does a merge
    }
    for (const Histogram* h : {&down, &read}) {
        EXPECT_EQ(h->count(), up.count());
        EXPECT_EQ(h->bins(), up.bins());
        EXPECT_EQ(h->max(), up.max());
        for (double p : {0.0, 0.1, 0.5, 0.9, 0.99}) EXPECT_EQ(h->percentile(p), up.percentile(p)) << p;
    }
    const size_t distinct = std::set<uint64_t>(values.begin(), values.end()).size();
    EXPECT_GT(distinct, Histogram::kExact);
    EXPECT_LT(up.bins(), distinct);  // coarse by the end
}

TEST(Agent, GuardStopsStaleCostlyAndLatencyBoundSlides) {
    auto run = [&](BalanceConfig cfg, Picos decideAt, Picos cost, Picos hop) {
        FakeHost ha;
        ha.cost = cost;
        ha.hop = hop;
        // (mean step 1 us, its work in the slab the policy gives: [0.75, 1])
        const BalanceStats s = oneRound(cfg, ha, 0.9, decideAt);
        return std::make_pair(ha.slabs.size(), s);
    };
    const BalanceConfig cfg = agentConfig();
    EXPECT_EQ(run(cfg, 21 * us, 0, 0).first, 1u);  // fresh, cheap, short hops: gives
    // Loads 4.05 intervals old (max 4): stale.
    auto [n1, s1] = run(cfg, 20 * us + 81 * us, 0, 0);
    EXPECT_EQ(n1, 0u);
    EXPECT_EQ(s1.skippedStale, 1u);
    // A hop of 4.1 us against 4 x the mean step of 1 us: latency-bound.
    auto [n2, s2] = run(cfg, 21 * us, 0, Picos(4.1 * us));
    EXPECT_EQ(n2, 0u);
    EXPECT_EQ(s2.skippedLatency, 1u);
    // The slab holds all the work recorded: it returns load 1 x 20 us x 10
    // intervals = 200 us.
    EXPECT_EQ(run(cfg, 21 * us, 199 * us, 0).first, 1u);
    auto [n3, s3] = run(cfg, 21 * us, 201 * us, 0);
    EXPECT_EQ(n3, 0u);
    EXPECT_EQ(s3.skippedCost, 1u);
    BalanceConfig off = cfg;
    off.guard = false;
    EXPECT_EQ(run(off, 20 * us + 200 * us, 1000 * us, 100 * us).first, 1u);
}

// A slab with no recorded work in it (the giver's work lies at 0.1, the
// slab is [0.75, 1]): `slide`'s guard counts no return and refuses even a
// 1 us slab; `relay`'s counts the slab by its thickness, a quarter of
// load 1 x 20 us x 10 intervals = 50 us, and gives it for up to that.
TEST(Agent, RelayPassesOnASlabWithNoWorkRecordedInIt) {
    auto run = [&](const std::string& policy, Picos cost) {
        FakeHost ha;
        ha.cost = cost;
        BalanceConfig cfg = agentConfig();
        cfg.policy = policy;
        const uint64_t refused = oneRound(cfg, ha, 0.1, 21 * us).skippedCost;
        return std::make_pair(ha.slabs.size(), refused);
    };
    EXPECT_EQ(run("slide", 1 * us), std::make_pair(size_t(0), uint64_t(1)));
    EXPECT_EQ(run("relay", 1 * us), std::make_pair(size_t(1), uint64_t(0)));
    EXPECT_EQ(run("relay", 49 * us), std::make_pair(size_t(1), uint64_t(0)));
    EXPECT_EQ(run("relay", 51 * us), std::make_pair(size_t(0), uint64_t(1)));
}

// --guard-wire: the giver's link to the taker had its wire busy for
// 16.2 us of the 20 us interval before the decision (0.81): over a share of
// 0.8 it does not give, under 0.82 it does, and off (0) the link's load does
// not count. Only the last interval counts: after one at 1.5 and one at 0.2
// it gives. And the rays the slab's work sends across count: the giver's one
// ray step in the 20 us span lies in the slab the policy gives ([0.75, 1]),
// so a ray message of 8 us on the wire adds 8 / 20 = 0.4 to a link at 0.5:
// 0.9, over 0.8; one of 4 us adds 0.2: 0.7, under.
TEST(Agent, BusyLinkGuardStopsSlidesAcrossASaturatedLink) {
    const Box world{Vec3(0.0), Vec3(2.0, 1.0, 1.0)};
    {
        BalanceConfig cfg = agentConfig();
        cfg.wireShare = 0.8;
        FakeHost ha, hb;
        BalanceAgent a(cfg, ha, world, 0, 2, false, true, 0.05), b(cfg, hb, world, 1, 2, true, false, 0.05);
        a.recordStep(0.9, 1 * us);
        ha.occupied = 30 * us;
        a.closeInterval(20 * us, 20 * us, 0, 0);
        settle(a);
        ha.occupied += 4 * us;
        a.closeInterval(40 * us, 40 * us, 0, 0);
        settle(a);
        b.closeInterval(20 * us, 0, 20 * us, 0);
        settle(b);
        a.onReport(+1, hb.reports[0].second, 41 * us);
        settle(a);
        EXPECT_EQ(ha.slabs.size(), 1u);
        EXPECT_EQ(a.stats().skippedBusyLink, 0u);
    }
    auto run = [&](double share, Picos busy = Picos(16.2 * us), Picos rayTime = 0) {
        BalanceConfig cfg = agentConfig();
        cfg.wireShare = share;
        FakeHost ha, hb;
        ha.rayTime = rayTime;
        BalanceAgent a(cfg, ha, world, 0, 2, false, true, 0.05), b(cfg, hb, world, 1, 2, true, false, 0.05);
        a.recordStep(0.9, 1 * us);
        ha.occupied = busy;  // sent during the interval that closes now
        a.closeInterval(20 * us, 20 * us, 0, 0);
        settle(a);
        ha.occupied += 20 * us;  // later sends do not count until the next interval closes
        b.closeInterval(20 * us, 0, 20 * us, 0);
        settle(b);
        a.onReport(+1, hb.reports[0].second, 21 * us);
        settle(a);
        return std::make_pair(ha.slabs.size(), a.stats().skippedBusyLink);
    };
    EXPECT_EQ(run(0.8), std::make_pair(size_t(0), uint64_t(1)));
    EXPECT_EQ(run(0.82), std::make_pair(size_t(1), uint64_t(0)));
    EXPECT_EQ(run(0), std::make_pair(size_t(1), uint64_t(0)));
    EXPECT_EQ(run(0.8, 10 * us, 8 * us), std::make_pair(size_t(0), uint64_t(1)));
    EXPECT_EQ(run(0.8, 10 * us, 4 * us), std::make_pair(size_t(1), uint64_t(0)));
}

// ---- The control lane (link.h) ----

namespace {

Message rays(int k) {  // 8 + 124 k bytes
    Message m;
    m.type = MsgType::Ray;
    if (k > 1) m.body().batch.assign(size_t(k), RayItem{});
    return m;
}

Message report() {  // 8 + 44 bytes
    Message m;
    m.type = MsgType::LoadReport;
    return m;
}

constexpr Picos ns = 1000;

// The links of these hand calculations: 1 byte per ns, 100 ns latency, 16
// data slots, and `lane` control slots.
LinkParams oneBytePerNs(int lane) {
    LinkParams p{100 * ns, 1e9, 16};
    p.controlDepth = lane;
    return p;
}

}  // namespace

// What the busy-link guard reads (Link::occupied): the link's wire time, or
// its slots' round trips over the slots when that is longer, each lane's
// slots on their own.
TEST(Link, OccupiedIsTheWireOrTheSlotsRoundTripByHand) {
    {  // 16 slots, 100 ns: three ray messages of 1,000 ns on the wire; their
       // slots, (1000 + 2 x 100) / 16 = 75 ns each, are the wider limit
        Link l("l", oneBytePerNs(0));
        for (int i = 0; i < 3; ++i) l.send(rays(8), 0);
        EXPECT_EQ(l.occupied(), 3000 * ns);
    }
    {  // 2 slots, 1 us: four reports of 52 ns, two on the wire (104 ns) and
       // two waiting for a slot; each will hold one for 52 + 2 x 1000 ns:
       // the link owes 4 x 2052 / 2, those waiting included
        Link l("l", LinkParams{1000 * ns, 1e9, 2});
        for (int i = 0; i < 4; ++i) l.send(report(), 0);
        EXPECT_EQ(l.stats().wireBusy(), 104 * ns);
        EXPECT_EQ(l.occupied(), 4104 * ns);
    }
    {  // one control slot, 100 ns: three reports take turns on it (the
       // 16 data slots do not carry them), each holding it 52 + 200 ns
        Link l("l", oneBytePerNs(1));
        for (int i = 0; i < 3; ++i) l.send(report(), 0);
        EXPECT_EQ(l.occupied(), 756 * ns);
        l.send(rays(8), 0);  // the wire, 3 x 52 + 1000 ns, is longer again
        EXPECT_EQ(l.occupied(), 1156 * ns);
    }
}

// A link's lookahead (how soon after its sender's time a message arrives at
// the soonest): its latency plus the smallest message it may carry on the
// wire; and it refuses a smaller one, since its receiver runs ahead by that.
TEST(Link, LookaheadIsTheLatencyAndTheSmallestMessageByHand) {
    // 100 ns and 1 byte/ns: a mesh link of rays alone, 8 + 124 bytes: 232 ns;
    // with a dynamic policy's acks, 8 + 8 bytes: 116 ns; a frame-buffer
    // port (a header): 108 ns.
    EXPECT_EQ(Link("rays", oneBytePerNs(0), smallestMeshMessage(false)).lookahead(), 232 * ns);
    EXPECT_EQ(Link("control", oneBytePerNs(0), smallestMeshMessage(true)).lookahead(), 116 * ns);
    EXPECT_EQ(Link("port", oneBytePerNs(0)).lookahead(), 108 * ns);
    // The soonest arrival is what the lookahead says: a ray sent at 5 ns.
    Link l("rays", oneBytePerNs(0), smallestMeshMessage(false));
    l.send(rays(1), 5 * ns);
    Picos a;
    ASSERT_TRUE(l.peekArrival(a));
    EXPECT_EQ(a, 5 * ns + l.lookahead());
    EXPECT_THROW(l.send(report(), 10 * ns), std::logic_error);  // 52 bytes on a link whose receiver counts on 132
    Link c("control", oneBytePerNs(2), smallestMeshMessage(true));
    EXPECT_NO_THROW(c.send(report(), 10 * ns));
}

TEST(ControlLane, GoesAheadOfWaitingRaysByHand) {
    // 1 byte/ns, 100 ns latency. Three ray messages of 1,000 bytes at t = 0
    // take the wire at 0, 1000 and 2000 ns. A load report (52 bytes) sent at
    // 500 ns goes on when the first leaves (1000), ahead of the other two,
    // which move back by 52 ns; a ray message sent after it goes after all.
    Link l("l", oneBytePerNs(2));
    for (int i = 0; i < 3; ++i) l.send(rays(8), 0);
    l.send(report(), 500 * ns);
    l.send(rays(8), 600 * ns);
    Picos a;
    ASSERT_TRUE(l.peekArrival(a));
    EXPECT_EQ(a, 1100 * ns);  // the first ray message: 1000 + 100
    EXPECT_FALSE(l.controlArrivedBy(1151 * ns));
    EXPECT_TRUE(l.controlArrivedBy(1152 * ns));  // 1000 + 52 + 100
    EXPECT_EQ(l.consume(1152 * ns).type, MsgType::Ray);  // consume takes the earliest arrival
    EXPECT_EQ(l.consumeControl(1152 * ns).type, MsgType::LoadReport);
    EXPECT_THROW(l.consume(2151 * ns), std::logic_error);  // the second: 1052 + 1000 + 100 = 2152
    EXPECT_EQ(l.consume(2152 * ns).type, MsgType::Ray);
    EXPECT_THROW(l.consume(3151 * ns), std::logic_error);  // the third: 2052 + 1000 + 100
    EXPECT_EQ(l.consume(3152 * ns).type, MsgType::Ray);
    EXPECT_THROW(l.consume(4151 * ns), std::logic_error);  // the one sent after the report: 3052 + 1000 + 100
    EXPECT_EQ(l.consume(4152 * ns).type, MsgType::Ray);
}

TEST(ControlLane, WithoutALaneTheReportWaitsBehindTheRays) {
    Link l("l", oneBytePerNs(0));
    for (int i = 0; i < 3; ++i) l.send(rays(8), 0);
    l.send(report(), 500 * ns);
    EXPECT_FALSE(l.controlArrivedBy(1000000 * ns));  // no lane: nothing to take ahead
    for (Picos t : {1100 * ns, 2100 * ns, 3100 * ns}) EXPECT_EQ(l.consume(t).type, MsgType::Ray);
    EXPECT_THROW(l.consume(3151 * ns), std::logic_error);  // 3000 + 52 + 100 = 3152
    EXPECT_EQ(l.consume(3152 * ns).type, MsgType::LoadReport);
}

TEST(ControlLane, HasItsOwnSlotsAndStaysFifo) {
    // One control slot: the second report waits until the first is consumed
    // (at 200 ns) and its slot has travelled back (100 ns later).
    Link l("l", oneBytePerNs(1));
    Message r1 = report(), r2 = report();
    r1.body().interval = 1;
    r2.body().interval = 2;
    l.send(std::move(r1), 0);
    l.send(std::move(r2), 0);
    EXPECT_TRUE(l.controlArrivedBy(152 * ns));
    EXPECT_EQ(l.consumeControl(200 * ns).body().interval, 1);
    EXPECT_FALSE(l.controlArrivedBy(451 * ns));  // slot back at 300, on the wire 52, latency 100: 452
    EXPECT_TRUE(l.controlArrivedBy(452 * ns));
    EXPECT_EQ(l.consumeControl(452 * ns).body().interval, 2);
}

TEST(ControlLane, TakesTurnsWithTheRaysWhileBothWaitByHand) {
    // As in GoesAheadOfWaitingRaysByHand, and a second report sent at
    // 1010 ns, while the first is on the wire and before the ray message it
    // went ahead of has started: that one goes first (1052 to 2052), then
    // the report (2052 to 2104), then the third ray message (2104 to 3104).
    Link l("l", oneBytePerNs(2));
    for (int i = 0; i < 3; ++i) l.send(rays(8), 0);
    l.send(report(), 500 * ns);
    l.send(report(), 1010 * ns);
    EXPECT_EQ(l.consume(1100 * ns).type, MsgType::Ray);
    EXPECT_EQ(l.consumeControl(1152 * ns).type, MsgType::LoadReport);
    EXPECT_FALSE(l.controlArrivedBy(2203 * ns));  // the second report: 2052 + 52 + 100
    EXPECT_THROW(l.consume(2151 * ns), std::logic_error);
    EXPECT_EQ(l.consume(2152 * ns).type, MsgType::Ray);  // 1052 + 1000 + 100
    EXPECT_TRUE(l.controlArrivedBy(2204 * ns));
    EXPECT_EQ(l.consumeControl(2204 * ns).type, MsgType::LoadReport);
    EXPECT_THROW(l.consume(3203 * ns), std::logic_error);
    EXPECT_EQ(l.consume(3204 * ns).type, MsgType::Ray);  // 2104 + 1000 + 100
}

TEST(ControlLane, AStreamOfReportsCannotStarveARay) {
    // Reports of 52 ns on the wire, sent back to back (0, 40, 92, 144, ...),
    // and a ray message of 1,000 ns sent at 10 ns. The first report is on
    // the wire at 0-52; the ray would start at 52, but the second report
    // (ready at 40) goes ahead of it (52-104); the third finds it owed its
    // turn, so the ray goes at 104-1104 and arrives at 1204 ns, whatever
    // follows. (When every report could move it back, it waited for all 200.)
    Link l("l", oneBytePerNs(1000));
    l.send(report(), 0);
    l.send(rays(8), 10 * ns);
    for (int i = 0; i < 200; ++i) l.send(report(), (40 + 52 * Picos(i)) * ns);
    EXPECT_EQ(l.consumeControl(152 * ns).type, MsgType::LoadReport);  // 0 + 52 + 100
    EXPECT_EQ(l.consumeControl(204 * ns).type, MsgType::LoadReport);  // 52 + 52 + 100
    EXPECT_FALSE(l.controlArrivedBy(1255 * ns));  // the third, after the ray: 1104 + 52 + 100
    EXPECT_THROW(l.consume(1203 * ns), std::logic_error);
    EXPECT_EQ(l.consume(1204 * ns).type, MsgType::Ray);
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

// ---- resplit: between frames (models/balance/frame_forecast.h, minimax_split.h, between_frames.h) ----

namespace {
// Part costs on a grid of m cells: the sum of the cells' costs, and `cut`
// more for a part whose ends lie on an edge listed (not the line's ends).
PartCosts sumOfCells(const std::vector<double>& cells, const std::map<int, double>& cut = {}) {
    const int m = int(cells.size());
    PartCosts c{m, std::vector<double>(size_t(m + 1) * size_t(m + 1), 0.0)};
    for (int i = 0; i < m; ++i)
        for (int j = i + 1; j <= m; ++j) {
            double x = 0;
            for (int k = i; k < j; ++k) x += cells[size_t(k)];
            for (int e : {i, j})
                if (auto it = cut.find(e); it != cut.end()) x += it->second;
            c.cost[size_t(i) * size_t(m + 1) + size_t(j)] = x;
        }
    return c;
}
}  // namespace

TEST(MinimaxSplit, EqualCellsSplitEvenly) {
    EXPECT_EQ(minimaxSplit(sumOfCells(std::vector<double>(12, 1.0)), 4, 1), (std::vector<int>{0, 3, 6, 9, 12}));
    // 3 1 1 3 in cells of 1, 1, 1, 1 each of 2: two parts of 4 each.
    EXPECT_EQ(minimaxSplit(sumOfCells({1.5, 1.5, 0.5, 0.5, 0.5, 0.5, 1.5, 1.5}), 2, 1), (std::vector<int>{0, 4, 8}));
}

TEST(MinimaxSplit, APlaneWhereManyRaysCrossCostsItsNeighbours) {
    // Ten cells of 1 in two parts: the middle, edge 5, gives 5 and 5; a
    // plane there cuts rays that cost each side 3 more (8 and 8), so the
    // plane moves to edge 4 or 6 (4 + 0 and 6, or 6 and 4): the dearest part 6.
    const std::vector<int> e = minimaxSplit(sumOfCells(std::vector<double>(10, 1.0), {{5, 3.0}}), 2, 1);
    EXPECT_TRUE(e == (std::vector<int>{0, 4, 10}) || e == (std::vector<int>{0, 6, 10})) << e[1];
    // Where the cut costs less than it saves, the plane stays.
    EXPECT_EQ(minimaxSplit(sumOfCells(std::vector<double>(10, 1.0), {{5, 0.5}}), 2, 1), (std::vector<int>{0, 5, 10}));
}

TEST(MinimaxSplit, AmongEqualDearestPartsTheRestShareEvenly) {
    // One cell of 10 dominates; the other 9 cells of 1 go to the two other
    // parts as evenly as they can (sum of squares): 4 and 5, not 1 and 8.
    std::vector<double> cells(10, 1.0);
    cells[0] = 10;
    const std::vector<int> e = minimaxSplit(sumOfCells(cells), 3, 1);
    EXPECT_EQ(e[1], 1);
    EXPECT_TRUE(e[2] == 5 || e[2] == 6) << e[2];
}

TEST(MinimaxSplit, EveryPartAtLeastTheMinimumWide) {
    std::vector<double> cells(12, 0.0);
    cells[0] = 100;  // all the work in the first cell: quarters would be one cell each
    const std::vector<int> e = minimaxSplit(sumOfCells(cells), 4, 3);
    EXPECT_EQ(e, (std::vector<int>{0, 3, 6, 9, 12}));
    EXPECT_THROW(minimaxSplit(sumOfCells(cells), 4, 4), std::invalid_argument);
    EXPECT_THROW(minimaxSplit(sumOfCells(cells), 0, 1), std::invalid_argument);
}

namespace {
// A report of an N x 1 x 2 mesh along x over [0, 1] (two columns, z = 0
// and z = 1), planes at k / N, each node busy `busy` with all of it spread
// over its box; `extra` edits it.
nlohmann::json forecastReport(int n, double busy) {
    nlohmann::json r;
    r["render_time_ns"] = 1000;
    r["config"]["mesh"] = {n, 1, 2};
    r["config"]["balance"]["axis"] = "x";
    for (int z = 0; z < 2; ++z) {
        for (int k = 1; k < n; ++k) r["boundaries"].push_back({{"column", {0, z}}, {"index", k}, {"history", {{0, double(k) / n}}}});
        for (int k = 0; k < n; ++k)
            r["nodes"].push_back({{"node", {k, 0, z}},
                                  {"box", {{double(k) / n, 0, z}, {double(k + 1) / n, 1, z + 1}}},
                                  {"busy_ns", busy}});
    }
    return r;
}
MachineConfig forecastMesh(int n) {
    MachineConfig m;
    m.dims = {n, 1, 2};
    m.balance.axis = 0;
    return m;
}
}  // namespace

TEST(FrameForecast, BusyTimesAndCutsByHand) {
    // Two nodes per column, 100 ns each spread over its half. Node 0 of
    // column z = 0 also crossed its upper face 40 times at 2 ns each (80
    // ns, not in its spread busy time), and the rays a plane would cut are
    // 10 going up at every position of [0, 1) (bins of 1/256: 128 per box).
    nlohmann::json r = forecastReport(2, 100);
    auto& w = r["nodes"][0]["work_by_position"];
    w = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 0}, {"ns", nlohmann::json::array()},
         {"face_handling_ns", 80.0}, {"face_crossings", 40}};
    w["cuts_up"] = {{"first_bin", 0}, {"rays", std::vector<double>(255, 10.0)}};
    r["nodes"][0]["busy_ns"] = 180.0;
    const MachineConfig m = forecastMesh(2);
    const FrameForecast f(r, m, InnerPlanes{{0.5}, {0.5}});
    // Held at 0.5: node 0 of column 0 does its 100, plus 10 cut rays at
    // 2 ns (its column's 80 ns / 40 crossings): 120; the others 100.
    EXPECT_NEAR(f.forecast({{0.5}, {0.5}}).nodeNs, 120, 1e-9);
    // At 0.25: node 1 has 50 of node 0's and its 100, and the cut: 170.
    EXPECT_NEAR(f.forecast({{0.25}, {0.5}}).nodeNs, 170, 1e-9);
    // The search evens column 0: x + 20 = (1 - x) ... busy below x is 200 x
    // for x < 0.5: 200 x + 20 = 200 - 200 x + 20 gives x = 0.5 again.
    const InnerPlanes p = f.perColumn();
    EXPECT_NEAR(p[0][0], 0.5, 1.0 / 256);
    EXPECT_NEAR(f.forecast(p).nodeNs, 120, 200.0 / 256 + 1e-9);
    // No links in the report: no wire time forecast.
    EXPECT_EQ(f.forecast(p).linkNs, 0);
}

TEST(FrameForecast, OneCellGrowthIsTheNewCellOverTheOld) {
    EXPECT_DOUBLE_EQ(oneCellGrowth(1.0, 1.0), 1.0);
    EXPECT_DOUBLE_EQ(oneCellGrowth(1.4, 1.0), 1.4);   // still one cell, 1.4 times as thick
    EXPECT_DOUBLE_EQ(oneCellGrowth(0.5, 1.0), 0.5);   // thinner: one cell, half as thick
    EXPECT_DOUBLE_EQ(oneCellGrowth(1.6, 1.0), 0.8);   // two cells of 0.8
    EXPECT_DOUBLE_EQ(oneCellGrowth(3.0, 1.0), 1.0);   // three cells of 1
}

TEST(FrameForecast, TestsWithinABoxOfOneCellAlongTheAxisGrowWithItsCell) {
    // Column z = 0, node 0 over [0, 0.5): 100 ns of work spread over its
    // box, 60 of it the tests of rays running across the axis inside it,
    // and its grid has one cell along x. Every other node: 100 ns spread.
    nlohmann::json r = forecastReport(2, 100);
    auto& w = r["nodes"][0]["work_by_position"];
    w = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 0}, {"ns", std::vector<double>(128, 100.0 / 128)},
         {"face_handling_ns", 0.0}, {"face_crossings", 0}};
    w["within"] = {{"first_bin", 0}, {"ns", std::vector<double>(128, 60.0 / 128)}};
    r["nodes"][0]["grid"] = {{"cells", {1, 3, 3}}, {"span", {{0, 0, 0}, {0.5, 1, 1}}}};
    const MachineConfig m = forecastMesh(2);
    const FrameForecast one(r, m, InnerPlanes{{0.5}, {0.5}});
    // Held: as measured.
    EXPECT_NEAR(one.forecast({{0.5}, {0.5}}).nodeNs, 100, 1e-9);
    // Node 0 to [0, 0.625), 1.25 times as thick, still one cell: its 100,
    // its 60 within 1.25 times (+15), and 25 of node 1's: 140.
    EXPECT_NEAR(one.forecast({{0.625}, {0.5}}).nodeNs, 140, 1e-9);
    // Node 0 to [0, 0.375): 75 of its own, of which 45 within at 0.75
    // (-11.25): 63.75. Node 1, [0.375, 1), 0.625 thick: node 0's last 25
    // (15 within, at 1.25 times: +3.75) and its 100: 128.75.
    EXPECT_NEAR(one.forecast({{0.375}, {0.5}}).nodeNs, 128.75, 1e-9);
    // With two cells along x the cells do not change with the box: no scaling.
    r["nodes"][0]["grid"]["cells"] = {2, 3, 3};
    const FrameForecast two(r, m, InnerPlanes{{0.5}, {0.5}});
    EXPECT_NEAR(two.forecast({{0.625}, {0.5}}).nodeNs, 125, 1e-9);
    EXPECT_NEAR(two.forecast({{0.375}, {0.5}}).nodeNs, 125, 1e-9);
}

TEST(FrameForecast, RaysAcrossColumnsArePassedWhereThePlanesDiffer) {
    // 30 rays left node 0 of column z = 0 for column z = 1 at x in the bin
    // [0.2, 0.2 + 1/256); a receive and a send cost 1 ns each (the column
    // handled 20 crossings for 20 ns).
    nlohmann::json r = forecastReport(2, 0);
    auto& w = r["nodes"][2]["work_by_position"];  // node 0 of column z = 1: its handling cost
    w = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 0}, {"ns", nlohmann::json::array()},
         {"face_handling_ns", 20.0}, {"face_crossings", 20}};
    r["nodes"][0]["work_by_position"] = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 51},
                                         {"ns", nlohmann::json::array()}};
    r["nodes"][0]["work_by_position"]["lateral"]["pz"] = {{"first_bin", 51}, {"rays", {30.0}}};
    r["links"] = nlohmann::json::array({{{"to", "+z"}, {"wire_ns", {{"ray", 300.0}}}}, {{"to", "fb"}, {"wire_ns", {{"ray", 1e6}}}}});
    const FrameForecast f(r, forecastMesh(2), InnerPlanes{{0.5}, {0.5}});
    // Planes alike: the rays go from node 0 to node 0, owner there; none passed.
    const FrameForecast::Forecast same = f.forecast({{0.5}, {0.5}});
    EXPECT_EQ(same.passes, 0);
    EXPECT_EQ(same.nodeNs, 0);
    // Column 1's plane at 0.1: x = 0.2 is its node 1's; node 0 passes the
    // 30 rays up: 30 x (1 + 1) ns, and the link up through 0.1 carries them.
    const FrameForecast::Forecast moved = f.forecast({{0.5}, {0.1}});
    EXPECT_EQ(moved.passes, 30);
    EXPECT_NEAR(moved.nodeNs, 60, 1e-9);
    // Wire per ray: 300 ns over the rays the links carried, the frame
    // buffer's links aside: the 30 across and 20 / 2 along the axis (each
    // crossing counted by both its nodes), 7.5 ns; the busiest link (the
    // one across, and the one up through 0.1) carries 30.
    EXPECT_NEAR(moved.linkNs, 225, 1e-9);
    EXPECT_NEAR(moved.frameNs, 225, 1e-9);
}

TEST(FrameForecast, ANodesLinkToANeighbouringColumnCarriesTheRaysOfItsPart) {
    // Node 0 of column z = 0 sent 2 rays to column z = 1 from each bin of
    // [0, 0.5) (256 rays); the links' rays took 512 ns on the wire, 2 ns
    // each; no other work. Its link there carries the rays of its part:
    // 512 ns with the plane at 0.5. Both searches halve its part (the plane
    // at 0.25: 128 rays, 256 ns); a search that saw only the nodes' busy
    // times and the links along the axis would see no cost anywhere.
    nlohmann::json r = forecastReport(2, 0);
    auto& w = r["nodes"][0]["work_by_position"];
    w = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 0}, {"ns", nlohmann::json::array()}};
    w["lateral"]["pz"] = {{"first_bin", 0}, {"rays", std::vector<double>(128, 2.0)}};
    r["links"] = nlohmann::json::array({{{"to", "+z"}, {"wire_ns", {{"ray", 512.0}}}}});
    const FrameForecast f(r, forecastMesh(2), InnerPlanes{{0.5}, {0.5}});
    EXPECT_NEAR(f.forecast({{0.5}, {0.5}}).linkNs, 512, 1e-9);
    for (const InnerPlanes& p : {f.perColumn(), f.aligned()}) {
        EXPECT_NEAR(p[0][0], 0.25, 1.0 / 256);
        EXPECT_NEAR(f.forecast({p[0], p[0]}).linkNs, 256, 2 * 2 + 1e-9);  // (within a bin's 2 rays)
    }
}

TEST(FrameForecast, ANodeAndALinkCloseTogetherMakeALongerFrame) {
    // The setup above (node 0 of column 0's link to column 1 carries 512
    // ns of rays with the plane at 0.5), each node also busy `busy` over
    // its box. Far apart, the frame is the dearer of the two; within
    // kTandem of each other, kTandem times the cheaper: the link queues the
    // rays behind it and the nodes after it get them late.
    for (const auto& [busy, frame] : {std::pair<double, double>{100, 512}, {2000, 2000}, {500, 550}, {540, 563.2}}) {
        nlohmann::json r = forecastReport(2, busy);
        auto& w = r["nodes"][0]["work_by_position"];
        w = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 0}, {"ns", nlohmann::json::array()}};
        w["lateral"]["pz"] = {{"first_bin", 0}, {"rays", std::vector<double>(128, 2.0)}};
        r["links"] = nlohmann::json::array({{{"to", "+z"}, {"wire_ns", {{"ray", 512.0}}}}});
        const FrameForecast::Forecast f = FrameForecast(r, forecastMesh(2), InnerPlanes{{0.5}, {0.5}}).forecast({{0.5}, {0.5}});
        EXPECT_NEAR(f.nodeNs, busy, 1e-9);
        EXPECT_NEAR(f.linkNs, 512, 1e-9);
        EXPECT_NEAR(f.frameNs, frame, 1e-9) << busy;
    }
}

TEST(Resplit, WorkByPositionKeepsOnlyTheSpanTraced) {
    // The world [0, 4] in 2 boxes: 256 bins of 1/64. Steps at 1.001 and
    // 1.01 share bin 64; one at 0.5 (bin 32) grows the span downwards, one
    // at 3.99 (bin 255) upwards; NaN is no position.
    WorkByPosition w(0, 4, 2);
    EXPECT_DOUBLE_EQ(w.binWidth(), 1.0 / 64);
    w.add(1.001, 3);
    w.add(1.01, 4);
    EXPECT_EQ(w.firstBin(), 64);
    EXPECT_EQ(w.bins(), (std::vector<double>{7}));
    w.add(0.5, 2);
    w.add(3.99, 1);
    w.add(std::nan(""), 100);
    EXPECT_EQ(w.firstBin(), 32);
    ASSERT_EQ(w.bins().size(), size_t(255 - 32 + 1));
    EXPECT_EQ(w.bins().front(), 2);
    EXPECT_EQ(w.bins()[64 - 32], 7);
    EXPECT_EQ(w.bins().back(), 1);
    double sum = 0;
    for (double b : w.bins()) sum += b;
    EXPECT_EQ(sum, 10);
}

TEST(Resplit, TimeAveragedPosition) {
    // At 1 for 2 ns, then at 3 for 2 ns.
    EXPECT_DOUBLE_EQ(timeAveraged({{0, 1}, {2, 3}}, 4), 2.0);
    // A move after the end does not count.
    EXPECT_DOUBLE_EQ(timeAveraged({{0, 1}, {2, 3}, {9, 100}}, 4), 2.0);
    EXPECT_DOUBLE_EQ(timeAveraged({{0, 5}}, 10), 5.0);
}

TEST(Agent, StartAtMovesEachFaceByItsOwnerAndHolds) {
    // Boxes [0,1] and [1,2] along x; the face's target 0.6 lies in the lower
    // box, so the lower node gives [0.6, 1] and the upper one gives nothing.
    BalanceConfig cfg = agentConfig();
    cfg.policy = "resplit";
    FakeHost ha, hb;
    hb.b = Box{Vec3(1.0, 0.0, 0.0), Vec3(2.0, 1.0, 1.0)};
    const Box world{Vec3(0.0), Vec3(2.0, 1.0, 1.0)};
    BalanceAgent a(cfg, ha, world, 0, 2, false, true, 0.05), b(cfg, hb, world, 1, 2, true, false, 0.05);
    const double nan = std::nan("");
    a.startAt(nan, 0.6);
    settle(a);
    b.startAt(0.6, nan);
    settle(b);
    ASSERT_EQ(ha.slabs.size(), 1u);
    EXPECT_EQ(ha.slabs[0], std::make_pair(+1, 0.6));
    EXPECT_TRUE(hb.slabs.empty());
    // Held for the frame: intervals close, nothing is reported or decided.
    for (int i = 1; i <= 3; ++i) {
        a.recordStep(0.3, 20 * us);
        a.closeInterval(Picos(i) * 20 * us, Picos(i) * 20 * us, 0, 5);
        settle(a);
        b.closeInterval(Picos(i) * 20 * us, 0, Picos(i) * 20 * us, 0);
        settle(b);
    }
    EXPECT_TRUE(ha.reports.empty());
    EXPECT_TRUE(hb.reports.empty());
    EXPECT_EQ(a.stats().decisions, 0u);
    // A target beyond the box: the owner gives as far as the minimum thickness allows.
    FakeHost hc;
    hc.b = Box{Vec3(1.0, 0.0, 0.0), Vec3(2.0, 1.0, 1.0)};
    BalanceAgent c(cfg, hc, world, 1, 2, true, false, 0.05);
    c.startAt(2.5, nan);
    settle(c);
    ASSERT_EQ(hc.slabs.size(), 1u);
    EXPECT_EQ(hc.slabs[0], std::make_pair(-1, 1.95));
}

// `sample`'s gather on a column of three boxes [0,1], [1,2], [2,3] along x,
// worked by hand. The lowest node's sample: 10 ps in each of its 64 bins
// (640); the middle one's: none; the top one's: 20 in its first bin. The
// column's 660 split in three parts of 220: 22 of the lowest node's bins
// (plane 0.34375), 22 more (0.6875), and the rest (420 - 220 + 20 = 220).
// The lowest node gives [0.34375, 1] up; the middle one gives up towards
// 0.6875 as far as its minimum thickness (0.05) allows, [1.05, 2], and
// passes on the rest once it has the lowest one's slab (tookSlab); the top
// one's plane lies below its box: it gives nothing.
TEST(Agent, SampleGathersUpTheColumnSplitsAtTheTopAndMovesEachFaceOnce) {
    BalanceConfig cfg = agentConfig();
    cfg.policy = "sample";
    FakeHost h[3];
    for (int k = 0; k < 3; ++k) h[k].b = Box{Vec3(double(k), 0.0, 0.0), Vec3(double(k + 1), 1.0, 1.0)};
    const Box world{Vec3(0.0), Vec3(3.0, 1.0, 1.0)};
    std::vector<std::unique_ptr<BalanceAgent>> a;
    for (int k = 0; k < 3; ++k) a.push_back(std::make_unique<BalanceAgent>(cfg, h[k], world, k, 3, k > 0, k < 2, 0.05));
    const std::array<bool, 6> none{};
    for (int k = 0; k < 3; ++k) {
        a[size_t(k)]->startSample(-1, none);
        EXPECT_EQ(h[k].begun, 1);
        EXPECT_TRUE(a[size_t(k)]->sampling());
    }
    for (int b = 0; b < 64; ++b) a[0]->recordSample((b + 0.5) / 64, 10);
    a[2]->recordSample(2.001, 20);
    a[1]->sampleReady(0);  // nothing goes up before the lowest node's sum
    a[2]->sampleReady(0);
    EXPECT_FALSE(a[1]->pending());
    a[0]->sampleReady(0);
    settle(*a[0]);
    ASSERT_EQ(h[0].reports.size(), 1u);
    EXPECT_EQ(h[0].reports[0].first, +1);
    EXPECT_EQ(h[0].reports[0].second.type, MsgType::Sample);
    EXPECT_EQ(h[0].reports[0].second.body().values.size(), size_t(2 * kSampleBins + 2));  // busiest box, edges, masses
    EXPECT_FALSE(a[0]->sampling());
    a[1]->onSample(h[0].reports[0].second, 0);
    settle(*a[1]);
    ASSERT_EQ(h[1].reports.size(), 1u);
    EXPECT_EQ(h[1].reports[0].second.body().values.size(), size_t(4 * kSampleBins + 2));
    a[2]->onSample(h[1].reports[0].second, 0);
    settle(*a[2]);
    ASSERT_EQ(h[2].reports.size(), 1u);
    const Message& planes = h[2].reports[0].second;
    EXPECT_EQ(h[2].reports[0].first, -1);
    ASSERT_EQ(planes.type, MsgType::Planes);
    ASSERT_EQ(planes.body().values.size(), 2u);
    EXPECT_NEAR(planes.body().values[0], 0.34375, 1e-6);
    EXPECT_NEAR(planes.body().values[1], 0.6875, 1e-6);
    EXPECT_TRUE(h[2].slabs.empty());
    a[1]->onPlanes(dirOf(0, +1), planes);
    settle(*a[1]);
    ASSERT_EQ(h[1].reports.size(), 2u);  // the planes, passed down
    EXPECT_EQ(h[1].reports[1].first, -1);
    ASSERT_EQ(h[1].slabs.size(), 1u);
    EXPECT_EQ(h[1].slabs[0], std::make_pair(+1, 1.05));
    a[0]->onPlanes(dirOf(0, +1), h[1].reports[1].second);
    settle(*a[0]);
    ASSERT_EQ(h[0].slabs.size(), 1u);
    EXPECT_EQ(h[0].slabs[0], std::make_pair(+1, planes.body().values[0]));
    EXPECT_EQ(h[0].reports.size(), 1u);  // nothing below it to pass them to
    // The middle node takes the lowest one's slab and passes on the rest to its plane.
    h[1].b.lo[0] = planes.body().values[0];
    a[1]->tookSlab();
    settle(*a[1]);
    ASSERT_EQ(h[1].slabs.size(), 2u);
    EXPECT_EQ(h[1].slabs[1], std::make_pair(+1, planes.body().values[1]));
    // Then it holds: planes twice, a sum it did not wait for, are errors.
    EXPECT_THROW(a[1]->onPlanes(dirOf(0, +1), planes), std::logic_error);
    EXPECT_THROW(a[1]->onSample(h[0].reports[0].second, 0), std::logic_error);
}

// The same gather on two boxes, the sum reaching the top late in the frame:
// the boxes as they stand would take 16 x 640 ps (the lowest box's sample),
// so at 10,000 ps less than 4 % of that frame is left to gain from: the
// planes sent down are none, and no face moves.
TEST(Agent, SampleHoldsWhereTheMoveComesTooLateToPay) {
    BalanceConfig cfg = agentConfig();
    cfg.policy = "sample";
    FakeHost h[2];
    for (int k = 0; k < 2; ++k) h[k].b = Box{Vec3(double(k), 0.0, 0.0), Vec3(double(k + 1), 1.0, 1.0)};
    const Box world{Vec3(0.0), Vec3(2.0, 1.0, 1.0)};
    BalanceAgent a(cfg, h[0], world, 0, 2, false, true, 0.05), b(cfg, h[1], world, 1, 2, true, false, 0.05);
    const std::array<bool, 6> none{};
    a.startSample(-1, none);
    b.startSample(-1, none);
    for (int k = 0; k < 64; ++k) a.recordSample((k + 0.5) / 64, 10);
    a.sampleReady(0);
    settle(a);
    b.sampleReady(10000);
    b.onSample(h[0].reports[0].second, 10000);
    settle(b);
    ASSERT_EQ(h[1].reports.size(), 1u);
    EXPECT_EQ(h[1].reports[0].second.type, MsgType::Planes);
    EXPECT_TRUE(h[1].reports[0].second.body().values.empty());
    a.onPlanes(dirOf(0, +1), h[1].reports[0].second);
    settle(a);
    EXPECT_TRUE(h[0].slabs.empty());
    EXPECT_TRUE(h[1].slabs.empty());
}

// What getting to new planes costs, by hand (move_forecast.h): boxes [0,1],
// [1,2], [2,3] along x holding 10, 20 and 30 objects; links of 100 ns and
// 42 GB/s (1 ns an object's 42 bytes), handling 40 + 40 ns a slide, grid
// updates 4 ns an object on each node (9 ns an object in all). Plane 1 from
// 1 to 2.5 crosses the second box and half the third: 2 hops of 180 ns,
// and 20 + 15 objects passed on average half of the chain's 2 + 1:
// 360 + 35 x 1.5 x 9 = 832.5 ns. Plane 2 stays. With the hops on the
// links (--hop-handling link), no handling: 200 + 472.5.
TEST(Resplit, GettingToNewPlanesCostsItsChainOfSlabs) {
    nlohmann::json r;
    const double objects[] = {10, 20, 30};
    for (int k = 0; k < 3; ++k)
        r["nodes"].push_back({{"node", {k, 0, 0}},
                              {"box", {{double(k), 0.0, 0.0}, {double(k + 1), 1.0, 1.0}}},
                              {"objects", objects[k]}});
    MachineConfig m;
    m.dims = {3, 1, 1};
    m.link.latency = 100000;
    m.link.bandwidth = 42e9;
    m.balance.rebuildCost = 4000;
    const InnerPlanes from{{1.0, 2.0}}, to{{2.5, 2.0}};
    EXPECT_NEAR(moveNs(r, m, from, to), 832.5, 1e-9);
    EXPECT_NEAR(moveNs(r, m, to, from), 832.5, 1e-9);  // the same chain back
    EXPECT_DOUBLE_EQ(moveNs(r, m, from, from), 0.0);
    m.hopsByLinks = true;
    EXPECT_NEAR(moveNs(r, m, from, to), 672.5, 1e-9);
}
