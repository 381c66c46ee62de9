// The balancing agent on its own: its rounds in lockstep with a neighbour,
// the ages of its reports, the guard, the start-at and sample moves,
// against values worked out by hand (no machine run).
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

// A column of `n` unit boxes along x, [k, k + 1], each with its agent under
// `sample` on a host of its own (the agents keep a reference to the
// configuration: it lives as long as they do).
struct SampleColumn {
    BalanceConfig cfg = agentConfig();
    std::vector<FakeHost> h;
    std::vector<std::unique_ptr<BalanceAgent>> a;
    explicit SampleColumn(int n) : h(size_t(n)) {
        cfg.policy = "sample";
        const Box world{Vec3(0.0), Vec3(double(n), 1.0, 1.0)};
        for (int k = 0; k < n; ++k) {
            h[size_t(k)].b = Box{Vec3(double(k), 0.0, 0.0), Vec3(double(k + 1), 1.0, 1.0)};
            a.push_back(std::make_unique<BalanceAgent>(cfg, h[size_t(k)], world, k, n, k > 0, k < n - 1, 0.05));
        }
    }
};

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
    SampleColumn c(3);
    std::vector<FakeHost>& h = c.h;
    std::vector<std::unique_ptr<BalanceAgent>>& a = c.a;
    for (int k = 0; k < 3; ++k) {
        a[size_t(k)]->startSample(true, {}, {});
        EXPECT_EQ(h[k].begun, 1);
        EXPECT_TRUE(a[size_t(k)]->sampling());
    }
    for (int b = 0; b < 64; ++b) a[0]->recordSample((b + 0.5) / 64, 10);
    a[2]->recordSample(2.001, 20);
    a[1]->sampleReady(0);  // nothing goes up before the lowest node's sum
    a[2]->sampleReady(0);
    EXPECT_FALSE(a[1]->pending());
    a[0]->sampleReady(7);  // (the climb starts at 7 ps)
    settle(*a[0]);
    ASSERT_EQ(h[0].reports.size(), 1u);
    EXPECT_EQ(h[0].reports[0].first, +1);
    EXPECT_EQ(h[0].reports[0].second.type, MsgType::Sample);
    // busiest box, start, 0 (no sides: no column beside it), 0 faces, the
    // box's pass and its one box, then the edges and masses: 64 bins in 63
    // cells, in kSampleValues
    EXPECT_EQ(h[0].reports[0].second.body().values.size(), size_t(kSampleValues));
    EXPECT_EQ(h[0].reports[0].second.body().values[1], 7);
    EXPECT_FALSE(a[0]->sampling());
    a[1]->onSample(h[0].reports[0].second, 9);
    settle(*a[1]);
    ASSERT_EQ(h[1].reports.size(), 1u);
    // 128 bins in 61 cells, beside a face, 2 passes and 2 boxes
    EXPECT_EQ(h[1].reports[0].second.body().values.size(), size_t(4 + 1 + 2 + 2 + 62 + 61));
    EXPECT_EQ(h[1].reports[0].second.body().values[1], 7);  // when the lowest node sent it, carried up
    a[2]->onSample(h[1].reports[0].second, 11);
    settle(*a[2]);
    ASSERT_EQ(h[2].reports.size(), 1u);
    const Message& planes = h[2].reports[0].second;
    EXPECT_EQ(h[2].reports[0].first, -1);
    ASSERT_EQ(planes.type, MsgType::Planes);
    ASSERT_EQ(planes.body().values.size(), 2u);
    EXPECT_NEAR(planes.body().values[0], 0.34375, 1e-6);
    EXPECT_NEAR(planes.body().values[1], 0.6875, 1e-6);
    EXPECT_TRUE(h[2].slabs.empty());
    a[1]->onPlanes(dirOf(0, +1), planes, 0);
    settle(*a[1]);
    ASSERT_EQ(h[1].reports.size(), 2u);  // the planes, passed down
    EXPECT_EQ(h[1].reports[1].first, -1);
    ASSERT_EQ(h[1].slabs.size(), 1u);
    EXPECT_EQ(h[1].slabs[0], std::make_pair(+1, 1.05));
    a[0]->onPlanes(dirOf(0, +1), h[1].reports[1].second, 0);
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
    EXPECT_THROW(a[1]->onPlanes(dirOf(0, +1), planes, 0), std::logic_error);
    EXPECT_THROW(a[1]->onSample(h[0].reports[0].second, 0), std::logic_error);
}

// --sample-end credit: the lowest node's sum waits for the frame buffer's
// word that the sample is done (a Sample message with no values, from
// below), not for its own sample's generation; the nodes above wait for
// the sum as before. A second word, a word to a node that is not the
// lowest, or a word without --sample-end credit are errors.
TEST(Agent, UnderSampleEndCreditTheClimbStartsAtTheFrameBuffersWord) {
    SampleColumn c(2);
    c.cfg.sampleCredit = true;
    for (int k = 0; k < 2; ++k) c.a[size_t(k)]->startSample(true, {}, {});
    c.a[0]->recordSample(0.5, 10);
    c.a[0]->sampleReady(5);  // generated: not yet
    c.a[1]->sampleReady(5);
    settle(*c.a[0]);
    EXPECT_TRUE(c.h[0].reports.empty());
    EXPECT_TRUE(c.a[0]->sampling());
    c.a[0]->recordSample(0.5, 30);  // (still recorded: the sample's rays are not all done)
    EXPECT_THROW(c.a[1]->onSample(Message::sample({}), 6), std::logic_error);  // not the lowest node
    c.a[0]->onSample(Message::sample({}), 20);
    settle(*c.a[0]);
    ASSERT_EQ(c.h[0].reports.size(), 1u);
    const Message& sum = c.h[0].reports[0].second;
    ASSERT_EQ(sum.type, MsgType::Sample);
    EXPECT_EQ(sum.body().values[1], 20);  // the climb starts at the word
    EXPECT_EQ(ColumnSample::of(sum.body().values).total(), 40);
    EXPECT_FALSE(c.a[0]->sampling());
    EXPECT_THROW(c.a[0]->onSample(Message::sample({}), 21), std::logic_error);  // twice
    c.a[1]->onSample(sum, 25);
    settle(*c.a[1]);
    ASSERT_EQ(c.h[1].reports.size(), 1u);
    EXPECT_EQ(c.h[1].reports[0].second.type, MsgType::Planes);
    // Without it the lowest node starts at its generation, and a word is an error.
    SampleColumn g(2);
    for (int k = 0; k < 2; ++k) g.a[size_t(k)]->startSample(true, {}, {});
    EXPECT_THROW(g.a[0]->onSample(Message::sample({}), 1), std::logic_error);
}

// Whether two lists of planes agree to 1e-9 (the split's bisection).
bool samePlanes(const std::vector<double>& a, const std::vector<double>& b) {
    if (a.size() != b.size()) return false;
    for (size_t k = 0; k < a.size(); ++k)
        if (std::abs(a[k] - b[k]) > 1e-9) return false;
    return true;
}

// Two columns of two boxes side by side along y, A below B: each gathers,
// or (B, without `bGathers`) holds with its faces at 1.
struct SideBySide {
    SampleColumn A{2}, B{2};
    const int toB = dirOf(1, +1), toA = dirOf(1, -1);
    explicit SideBySide(bool bGathers = true) {
        for (int k = 0; k < 2; ++k) {
            A.a[size_t(k)]->startSample(true, {toB}, {});
            B.a[size_t(k)]->startSample(bGathers, {toA}, k == 1 ? std::vector<double>{1} : std::vector<double>{});
        }
    }
    // The sample is in: each gathering column's sum climbs to its top node.
    void gather() {
        for (SampleColumn* c : {&A, &B}) {
            if (c->h[0].begun == 0) continue;  // (a column that holds)
            c->a[0]->sampleReady(0);
            settle(*c->a[0]);
            c->a[1]->sampleReady(0);
            c->a[1]->onSample(c->h[0].reports[0].second, 0);
            settle(*c->a[1]);
        }
    }
    // The top nodes hear each other's message of a round (0: the proposal, 1: the verdict).
    void exchange(int round) {
        A.a[1]->onPlanes(toB, B.h[1].sent[size_t(round)].second, 0);
        B.a[1]->onPlanes(toA, A.h[1].sent[size_t(round)].second, 0);
        settle(*A.a[1]);
        settle(*B.a[1]);
    }
};

// Two columns side by side (A below B along y), each of two boxes [0, 1]
// and [1, 2] along x. A's sample did all its work in its lower box (640 ps),
// B's in its upper one: alone, A would move its plane to 0.5 and B to 1.5
// (each part 320, against 640). The rays across their common side, in A's
// lower box: `side` per bin. The top nodes tell each other their
// proposals, then whether they would move, and only then decide.
//  - Heavy crossings (100 per bin, 6,400): with A at 0.5 and B at 1.5,
//    those in [0.5, 1] (3,200) would be A's upper node's and B's lower
//    node's, passed between them at half each: 320 + 1,600 = 1,920 in
//    either part of A, against 640 holding (and B likewise, its crossings
//    in [1, 1.5]). Neither says it moves, and against the faces as they
//    stand moving costs each the same: both hold.
//  - Light (1 per bin): 320 + 16 against 640: both move.
TEST(Agent, ColumnsSideBySideMoveOnlyWhereMovingTogetherPays) {
    for (const double side : {100.0, 1.0}) {
        SideBySide t;
        SampleColumn &A = t.A, &B = t.B;
        for (int b = 0; b < 64; ++b) {
            A.a[0]->recordSample((b + 0.5) / 64, 10);
            A.a[0]->recordSide((b + 0.5) / 64, side);
            B.a[1]->recordSample(1 + (b + 0.5) / 64, 10);
            B.a[1]->recordSide(1 + (b + 0.5) / 64, side);
        }
        t.gather();
        // Each top node has proposed (its planes, then its faces as they stand), and waits.
        ASSERT_EQ(A.h[1].sent.size(), 1u);
        EXPECT_EQ(A.h[1].sent[0].first, t.toB);
        EXPECT_TRUE(samePlanes(A.h[1].sent[0].second.body().values, {0.5, 1}));
        ASSERT_EQ(B.h[1].sent.size(), 1u);
        EXPECT_TRUE(samePlanes(B.h[1].sent[0].second.body().values, {1.5, 1}));
        EXPECT_TRUE(A.h[1].reports.empty());  // (no planes down yet)
        t.exchange(0);
        // Then whether each would move; then each decides.
        ASSERT_EQ(A.h[1].sent.size(), 2u);
        ASSERT_EQ(B.h[1].sent.size(), 2u);
        const bool together = side < 10;
        EXPECT_EQ(A.h[1].sent[1].second.body().values, std::vector<double>{together ? 1.0 : 0.0});
        EXPECT_EQ(B.h[1].sent[1].second.body().values, std::vector<double>{together ? 1.0 : 0.0});
        EXPECT_TRUE(A.h[1].reports.empty());
        t.exchange(1);
        ASSERT_EQ(A.h[1].reports.size(), 1u);
        ASSERT_EQ(B.h[1].reports.size(), 1u);
        EXPECT_TRUE(samePlanes(A.h[1].reports[0].second.body().values, together ? std::vector<double>{0.5} : std::vector<double>{}))
            << side;
        EXPECT_TRUE(samePlanes(B.h[1].reports[0].second.body().values, together ? std::vector<double>{1.5} : std::vector<double>{}))
            << side;
        // A third message from beside is an error.
        EXPECT_THROW(A.a[1]->onPlanes(t.toB, B.h[1].sent[1].second, 0), std::logic_error);
    }
}

// The planes beside as they will be: a column counts the proposal of a
// column beside only where that column said it would move. A's work is in
// its lower box (it proposes 0.5), B's in [0, 0.5] (it proposes 0.25);
// their crossings are heavy (100 per bin): A's in [0.5, 1], B's in
// [0.25, 0.5]. If both moved, A's would pass nothing (A's [0.5, 1] is its
// upper node's, as B's at 0.25) and A says it would move; B's [0.25, 0.5]
// would be its upper node's and A's lower one's: 1,600 passes each side,
// and B says it would not. So A counts B's faces as they stand (1): its
// [0.5, 1] would then pass 1,600 each way, and A holds too. (Counting B's
// proposal, A would move, and pass every such ray.)
TEST(Agent, AColumnCountsOnlyTheMovesItsNeighboursSayTheyMake) {
    SideBySide t;
    SampleColumn &A = t.A, &B = t.B;
    for (int b = 0; b < 64; ++b) {
        A.a[0]->recordSample((b + 0.5) / 64, 10);
        if (b >= 32) A.a[0]->recordSide((b + 0.5) / 64, 100);
        B.a[0]->recordSample((b + 0.5) / 128, 10);
        if (b >= 32) B.a[0]->recordSide((b + 0.5) / 128, 100);
    }
    t.gather();
    EXPECT_TRUE(samePlanes(B.h[1].sent[0].second.body().values, {0.25, 1}));
    t.exchange(0);
    t.exchange(1);
    EXPECT_EQ(A.h[1].sent[1].second.body().values, std::vector<double>{1.0});
    EXPECT_EQ(B.h[1].sent[1].second.body().values, std::vector<double>{0.0});
    ASSERT_EQ(A.h[1].reports.size(), 1u);
    EXPECT_TRUE(A.h[1].reports[0].second.body().values.empty());
    EXPECT_TRUE(B.h[1].reports[0].second.body().values.empty());
}

// A column beside one that holds (its faces at 1): the holding column's top
// node proposes its faces at once and says it holds; the gathering one moves
// where that pays against them (light crossings: 0.5).
TEST(Agent, AColumnThatHoldsProposesItsFacesAtOnce) {
    SideBySide t(false);
    SampleColumn &A = t.A, &B = t.B;
    settle(*B.a[1]);
    ASSERT_EQ(B.h[1].sent.size(), 2u);
    EXPECT_EQ(B.h[1].sent[0].second.body().values, (std::vector<double>{1, 1}));
    EXPECT_EQ(B.h[1].sent[1].second.body().values, std::vector<double>{0.0});
    EXPECT_EQ(B.h[1].begun, 0);  // (it gathers nothing)
    for (int b = 0; b < 64; ++b) {
        A.a[0]->recordSample((b + 0.5) / 64, 10);
        A.a[0]->recordSide((b + 0.5) / 64, 1);
    }
    for (int k = 0; k < 2; ++k) A.a[1]->onPlanes(t.toB, B.h[1].sent[size_t(k)].second, 0);
    t.gather();
    ASSERT_EQ(A.h[1].reports.size(), 1u);
    EXPECT_TRUE(samePlanes(A.h[1].reports[0].second.body().values, {0.5}));
}

// The same gather on two boxes, the sum reaching the top late in the frame:
// the boxes as they stand would take 16 x 640 ps (the lowest box's sample),
// so at 10,000 ps less than 4 % of that frame is left to gain from: the
// planes sent down are none, and no face moves.
TEST(Agent, SampleHoldsWhereTheMoveComesTooLateToPay) {
    SampleColumn c(2);
    std::vector<FakeHost>& h = c.h;
    BalanceAgent &a = *c.a[0], &b = *c.a[1];
    a.startSample(true, {}, {});
    b.startSample(true, {}, {});
    for (int k = 0; k < 64; ++k) a.recordSample((k + 0.5) / 64, 10);
    a.sampleReady(0);
    settle(a);
    b.sampleReady(10000);
    b.onSample(h[0].reports[0].second, 10000);
    settle(b);
    ASSERT_EQ(h[1].reports.size(), 1u);
    EXPECT_EQ(h[1].reports[0].second.type, MsgType::Planes);
    EXPECT_TRUE(h[1].reports[0].second.body().values.empty());
    a.onPlanes(dirOf(0, +1), h[1].reports[0].second, 0);
    settle(a);
    EXPECT_TRUE(h[0].slabs.empty());
    EXPECT_TRUE(h[1].slabs.empty());
}
