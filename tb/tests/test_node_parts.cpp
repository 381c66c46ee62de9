// The node's parts on their own, without a machine: its time ledger, where
// it routes a ray, the slab exchange's geometry and objects, the cost
// model, the ray batcher, the frame-buffer outbox, the queue's high-water
// mark, the messages' sizes and the mesh's geometry. Every expected value
// is worked out here by hand.
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "busy_by_hand.h"
#include "node/busy_parts.h"
#include "node/cost_model.h"
#include "node/fb_outbox.h"
#include "base/mesh_geometry.h"
#include "channel/message.h"
#include "base/queue_marks.h"
#include "channel/ray_batcher.h"
#include "channel/route.h"
#include "balance/slab.h"
#include "node/time_ledger.h"

using namespace rt;

namespace {

// A step of `cost`, all of it one kind of work.
BusyParts of(Picos cost, int kind = kVoxelSteps) {
    BusyParts p{};
    p[size_t(kind)] = cost;
    return p;
}

auto kernelAt(Picos t) {
    return [t] { return t; };
}

RayJob job(Vec3 o, Vec3 d, double t0 = 0, uint32_t pixel = 0) {
    RayJob j;
    j.ray = Ray(o, d);
    j.t0 = t0;
    j.tEnd = 1e30;
    j.pixel = pixel;
    return j;
}

Shape sphere(Vec3 c, double r, uint32_t id) { return Shape{Sphere{c, r, false}, 0, id}; }

Contribution contribution(uint32_t pixel) {
    Contribution c;
    c.pixel = pixel;
    return c;
}

}  // namespace

// ---- The time ledger (time_ledger.h) ----

TEST(TimeLedger, LockstepCutsTheStepThatRunsPastTheEnd) {
    NodeTimes t;
    TimeLedger l(t);
    l.configure(false, false);
    l.charge(of(300), 300, kernelAt(0));   // busy 0..300
    l.startWaiting(300);
    l.endWaiting(500, kernelAt(500));  // waited 300..500
    l.charge(of(200), 700, kernelAt(500));  // busy 500..700, the frame ends at 600
    l.endFrame(600, true, "n");
    EXPECT_EQ(t.busy, 400u);
    EXPECT_EQ(t.wait, 200u);
    EXPECT_EQ(t.lastActive, 600u);
    EXPECT_EQ(t.busy + t.wait, 600u);
}

TEST(TimeLedger, WaitingOrBlockedAtTheEndLastsUntilIt) {
    NodeTimes w;
    TimeLedger waiting(w);
    waiting.configure(true, false);
    waiting.charge(of(100), 100, kernelAt(0));
    waiting.startWaiting(100);
    waiting.endFrame(1000, true, "n");
    EXPECT_EQ(w.busy, 100u);
    EXPECT_EQ(w.wait, 900u);
    EXPECT_FALSE(w.waiting);

    NodeTimes b;
    TimeLedger blocked(b);
    blocked.configure(true, false);
    blocked.charge(of(100), 100, kernelAt(0));
    blocked.startBlocked(100, kDirs + 2);
    EXPECT_TRUE(blocked.blocking());
    blocked.endFrame(400, true, "n");
    EXPECT_EQ(b.blocked, 300u);
    EXPECT_EQ(b.wait, 300u);  // blocked time is wait
    EXPECT_EQ(b.busy + b.wait, 400u);
    EXPECT_EQ(b.blockedOn, kDirs + 2);
}

TEST(TimeLedger, BlockedTimeIsWaitWhenItEnds) {
    NodeTimes t;
    TimeLedger l(t);
    l.startBlocked(50, 1);
    EXPECT_EQ(l.endBlocked(80), 30u);
    EXPECT_EQ(t.blocked, 30u);
    EXPECT_EQ(t.wait, 30u);
    EXPECT_FALSE(l.blocking());
}

TEST(TimeLedger, AheadWithoutATimelineIdledPastTheEnd) {
    NodeTimes t;
    TimeLedger l(t);
    l.configure(true, false);
    l.charge(of(100), 100, kernelAt(0));
    l.startWaiting(100);
    l.endWaiting(900, kernelAt(0));  // idled ahead of the kernel to 900
    l.endFrame(500, true, "n");      // the frame ended at 500
    EXPECT_EQ(t.busy, 100u);
    EXPECT_EQ(t.wait, 400u);
}

TEST(TimeLedger, AStepPastTheEndWithoutAPolicyIsABugUnlessTheRunWasStopped) {
    NodeTimes t;
    TimeLedger l(t);
    l.configure(true, false);
    l.charge(of(1000), 1000, kernelAt(0));
    EXPECT_THROW(l.endFrame(600, true, "n"), std::logic_error);
    NodeTimes s;
    TimeLedger stopped(s);
    stopped.configure(true, false);
    stopped.charge(of(1000), 1000, kernelAt(0));
    stopped.endFrame(600, false, "n");  // stopped at 600: busy up to then
    EXPECT_EQ(s.busy, 600u);
    EXPECT_EQ(s.wait, 0u);
    EXPECT_EQ(s.lastActive, 600u);
}

TEST(TimeLedger, TheTimelineGivesTheFiguresAtTheEnd) {
    NodeTimes t;
    TimeLedger l(t);
    l.configure(true, true);
    l.charge(of(100), 100, kernelAt(0));    // busy 0..100
    l.startWaiting(100);
    l.endWaiting(400, kernelAt(0));     // wait 100..400
    l.charge(of(300), 700, kernelAt(0));    // busy 400..700
    l.startWaiting(700);
    l.endWaiting(800, kernelAt(0));     // wait 700..800
    l.charge(of(100), 900, kernelAt(0));    // busy 800..900
    l.endFrame(500, true, "n");         // in the second step: 100 of it before the end
    EXPECT_EQ(t.busy, 200u);
    EXPECT_EQ(t.wait, 300u);
    EXPECT_EQ(t.lastActive, 500u);
}

// ---- Busy time by kind of work (busy_parts.h) ----

TEST(BusyParts, ScaledPartsSumExactlyAndFollowTheProportions) {
    BusyParts p{};
    p[0] = 1;
    p[kSend] = 1;
    p[kReceive] = 1;
    const BusyParts q = scaledTo(p, 10);  // 10/3 each: the one picosecond left goes to the lowest kind
    EXPECT_EQ(q[0], 4u);
    EXPECT_EQ(q[kSend], 3u);
    EXPECT_EQ(q[kReceive], 3u);
    EXPECT_EQ(sumOf(q), 10u);
    BusyParts big{};  // near the counter's end: 128-bit products
    big[kShading] = Picos(1) << 61;
    big[kSend] = (Picos(1) << 61) - 1;
    EXPECT_EQ(sumOf(scaledTo(big, (Picos(1) << 62) - 7)), (Picos(1) << 62) - 7);
    EXPECT_EQ(scaledTo(BusyParts{}, 5)[kVoxelSteps], 5u);  // nothing to follow: the fallback kind
}

TEST(BusyParts, TrimTakesFromTheLastStepFirst) {
    BusyParts total = of(500, kShading);
    total[kSend] = 100;
    BusyParts last = of(100, kSend);
    trim(total, last, 60);  // within the last step: all of it from its kind
    EXPECT_EQ(total[kSend], 40u);
    EXPECT_EQ(total[kShading], 500u);
    trim(total, last, 140);  // more than is left of it: 40 from send, then 100 of the rest, in proportion
    EXPECT_EQ(sumOf(total), 400u);
    EXPECT_EQ(total[kSend], 0u);
}

TEST(TimeLedger, KindsOfWorkFollowTheCutAtTheEnd) {
    NodeTimes t;
    TimeLedger l(t);
    l.configure(true, true);
    l.charge(of(100, kShading), 100, kernelAt(0));
    l.startWaiting(100);
    l.endWaiting(400, kernelAt(0));
    BusyParts mixed = of(200, kSend);
    mixed[kReceive] = 100;
    l.charge(mixed, 700, kernelAt(0));  // busy 400..700: a third of it runs before 500
    l.endFrame(500, true, "n");
    EXPECT_EQ(t.busyBy[kShading], 100u);
    EXPECT_EQ(t.busyBy[kSend] + t.busyBy[kReceive], 100u);
    EXPECT_EQ(t.busyBy[kSend], 67u);  // 200/3 = 66.7 and 100/3 = 33.3: the larger remainder gets the picosecond
    EXPECT_EQ(sumOf(t.busyBy), t.busy);

    NodeTimes u;  // lockstep: the last step cut
    TimeLedger lock(u);
    lock.configure(false, false);
    lock.charge(of(300, kShading), 300, kernelAt(0));
    lock.charge(of(200, kSend), 500, kernelAt(300));
    lock.endFrame(400, true, "n");
    EXPECT_EQ(u.busyBy[kShading], 300u);
    EXPECT_EQ(u.busyBy[kSend], 100u);
}

TEST(CostModel, PartsSumToTheStepAtAnySpeed) {
    const Costs c = test::distinctCosts();  // sphere 7, voxel 3, send 23 ns, ...
    Counters before, after;
    after.tests = {3, 1, 2};
    after.voxelSteps = 5;
    after.shadings = 1;
    for (double speed : {1.0, 3.0, 0.7}) {
        const CostModel m(c, speed, 20000);
        const BusyParts p = m.stepParts(before, after, 2, 1, 1);
        EXPECT_EQ(sumOf(p), m.step(before, after, 2, 1, 1)) << speed;
        if (speed == 1.0) {
            EXPECT_EQ(p[0], 21000u);
            EXPECT_EQ(p[kSend], 46000u);
            EXPECT_EQ(p[kVoxelSteps], 15000u);
        }
        const BusyParts q = m.messageParts(1, 2, 3, true);
        EXPECT_EQ(sumOf(q), m.step(before, before, 1, 2, 0) + m.rebuild(3)) << speed;
        EXPECT_EQ(q[kSlabRebuild], m.rebuild(3));
    }
}

TEST(TimeLedger, TheTimelineKeepsWhatTheKernelHasNotPassed) {
    NodeTimes t;
    TimeLedger l(t);
    l.configure(true, true);
    Picos now = 0;
    for (int i = 0; i < 10000; ++i) {  // steps of 10 and waits of 10, the kernel 30 behind
        now += 10;
        l.charge(of(10), now, kernelAt(now - 30));
        l.startWaiting(now);
        now += 10;
        l.endWaiting(now, kernelAt(now - 30));
    }
    const Picos end = now - 25;  // in the last step but one's wait
    l.endFrame(end, true, "n");
    EXPECT_EQ(t.busy + t.wait, end);
    EXPECT_EQ(t.busy, 9999u * 10);
}

TEST(TimeLedger, TimeThatPassedWithoutACheckpointIsABugItSays) {
    NodeTimes t;
    TimeLedger l(t);
    l.configure(true, true);
    l.charge(of(10), 10, kernelAt(0));
    l.startBlocked(10, PosX);
    l.endBlocked(50);  // (the node checkpoints after a send that blocked: Node::endSend)
    EXPECT_THROW(l.endFrame(30, true, "n"), std::logic_error);
}

// ---- Where a ray is forwarded (route.h) ----

TEST(Route, OwnedRaysStayAndOthersGoTowardsTheirOwner) {
    const Box box{Vec3(1, 0, 0), Vec3(2, 1, 1)};
    const RayJob inside = job(Vec3(0, 0.5, 0.5), Vec3(1, 0, 0), 1.5);
    EXPECT_EQ(routeRay(inside, boxSlabs(inside.ray, box), box), -1);
    const RayJob before = job(Vec3(0, 0.5, 0.5), Vec3(1, 0, 0), 0.5);  // at x = 0.5: the -x neighbour's
    EXPECT_EQ(routeRay(before, boxSlabs(before.ray, box), box), NegX);
    const RayJob after = job(Vec3(0, 0.5, 0.5), Vec3(1, 0, 0), 2.0);  // at x = 2: the half-open rule gives it to +x
    EXPECT_EQ(routeRay(after, boxSlabs(after.ray, box), box), PosX);
    const RayJob backwards = job(Vec3(3, 0.5, 0.5), Vec3(-1, 0, 0), 0.5);  // at x = 2.5, moving -x
    EXPECT_EQ(routeRay(backwards, boxSlabs(backwards.ray, box), box), PosX);
    // Not moving along y, and outside the box's y range: by its origin.
    const RayJob above = job(Vec3(1.5, 1.5, 0.5), Vec3(0, 0, 1), 0.0);
    EXPECT_EQ(routeRay(above, boxSlabs(above.ray, box), box), PosY);
    // The first axis that does not own t0 picks: z here, x below.
    const RayJob below = job(Vec3(1.5, 0.5, -0.5), Vec3(1, 0, 0), 0.0);
    EXPECT_EQ(routeRay(below, boxSlabs(below.ray, box), box), NegZ);
    const RayJob beyond = job(Vec3(1.5, 0.5, -0.5), Vec3(1, 0, 0), 1.0);
    EXPECT_EQ(routeRay(beyond, boxSlabs(beyond.ray, box), box), PosX);
}

// ---- Slab exchange (slab.h) ----

TEST(Slab, FacesMoveAndTheSlabLiesBetween) {
    const Box b{Vec3(0.0), Vec3(1.0)};
    const Box upper = withFace(b, 0, +1, 0.7), lower = withFace(b, 2, -1, 0.3);
    EXPECT_EQ(upper.hi.x, 0.7);
    EXPECT_EQ(upper.lo.x, 0.0);
    EXPECT_EQ(lower.lo.z, 0.3);
    EXPECT_EQ(lower.hi.z, 1.0);
    const Box give = slabOf(b, 0, +1, 0.7);  // what the upper face gives: 0.7 .. 1
    EXPECT_EQ(give.lo.x, 0.7);
    EXPECT_EQ(give.hi.x, 1.0);
    const Box giveLow = slabOf(b, 0, -1, 0.3);
    EXPECT_EQ(giveLow.lo.x, 0.0);
    EXPECT_EQ(giveLow.hi.x, 0.3);
}

TEST(Slab, ObjectsAcrossTheFaceGoAndStayAndAreTakenOnce) {
    const Box b{Vec3(0.0), Vec3(1.0)};
    const std::vector<Shape> objects{sphere(Vec3(0.2, 0.5, 0.5), 0.1, 1), sphere(Vec3(0.7, 0.5, 0.5), 0.1, 2),
                                     sphere(Vec3(0.9, 0.5, 0.5), 0.05, 3)};
    const ObjectSplit s = splitObjects(objects, slabOf(b, 0, +1, 0.7), withFace(b, 0, +1, 0.7), 1e-9);
    ASSERT_EQ(s.give.size(), 2u);  // 2 straddles the face, 3 is inside the slab
    EXPECT_EQ(s.give[0].id, 2u);
    EXPECT_EQ(s.give[1].id, 3u);
    ASSERT_EQ(s.keep.size(), 2u);
    EXPECT_EQ(s.keep[0].id, 1u);
    EXPECT_EQ(s.keep[1].id, 2u);
    const std::vector<Shape> taken = uniteObjects({sphere(Vec3(1.2, 0.5, 0.5), 0.1, 4), objects[1]}, s.give);
    ASSERT_EQ(taken.size(), 3u);  // 4, 2 (already held), 3
    EXPECT_EQ(taken[2].id, 3u);
    const SlabLoad load = slabLoad(objects, slabOf(b, 0, +1, 0.7), 1e-9);
    EXPECT_EQ(load.objects, 2u);
    EXPECT_EQ(load.bytes, kHeaderBytes + kSlideBytes + 2 * objectBytes(objects[1]));
    EXPECT_EQ(load.bytes, Message::slide(0.7, s.give).bytes());
}

// ---- The cost model (cost_model.h) ----

TEST(CostModel, OperationsTimesTheirCostsOverTheSpeed) {
    const Costs c = test::distinctCosts();  // sphere 7, polygon 11, cone 13, voxel 3, raygen 17, shade 19, send 23, recv 29 ns
    Counters before, after;
    before.tests = {1, 1, 1};
    after.tests = {4, 3, 3};  // 3 spheres, 2 polygons, 2 cones
    after.voxelSteps = 5;
    after.shadings = 1;
    // 3 x 7 + 2 x 11 + 2 x 13 + 5 x 3 + 19, two sends, one receive and one primary ray generated
    const Picos atOne = 21000 + 22000 + 26000 + 15000 + 19000 + 2 * 23000 + 29000 + 17000;
    EXPECT_EQ(CostModel(c, 1.0, 9).step(before, after, 2, 1, 1), atOne);
    EXPECT_EQ(CostModel(c, 2.0, 9).step(before, after, 2, 1, 1), atOne / 2);
    EXPECT_EQ(CostModel(c, 3.0, 9).step(before, after, 0, 0, 0), 34333u);  // 103,000 / 3, rounded
    EXPECT_EQ(CostModel(c, 1.0, 9).rebuild(5), 45u);
    EXPECT_EQ(CostModel(c, 4.0, 9).rebuild(5), 11u);  // 45 / 4 = 11.25
    EXPECT_DOUBLE_EQ(CostModel(c, 2.0, 9).slabHandling(5), (23000 + 29000 + 2 * 5 * 9) / 2.0);
}

// ---- The ray batcher (ray_batcher.h) ----

TEST(RayBatcher, AMessagePerRayOrFullBatchesThenTheRest) {
    Outbox out;
    RayBatcher one(1);
    one.add(PosX, job(Vec3(0.0), Vec3(1, 0, 0)), 3, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].first, PosX);
    EXPECT_FALSE(out[0].second.batched());
    EXPECT_EQ(out[0].second.ray.creditExp, 3);
    EXPECT_EQ(out[0].second.bytes(), kHeaderBytes + kRayBytes);

    out.clear();
    RayBatcher three(3);
    for (int i = 0; i < 4; ++i) three.add(NegY, job(Vec3(0.0), Vec3(0, -1, 0), 0, uint32_t(i)), 1, out);
    three.add(PosZ, job(Vec3(0.0), Vec3(0, 0, 1)), 1, out);
    ASSERT_EQ(out.size(), 1u);  // the full batch of 3
    EXPECT_EQ(out[0].second.rayCount(), 3u);
    EXPECT_EQ(out[0].second.rayAt(2).pixel, 2u);
    EXPECT_EQ(out[0].second.bytes(), kHeaderBytes + 3 * kRayBytes);
    EXPECT_EQ(three.held(), 2u);
    three.flush(out);
    ASSERT_EQ(out.size(), 3u);  // then -y's one ray, then +z's, in direction order
    EXPECT_EQ(out[1].first, NegY);
    EXPECT_EQ(out[1].second.rayAt(0).pixel, 3u);
    EXPECT_EQ(out[2].first, PosZ);
    EXPECT_EQ(three.held(), 0u);
}

TEST(RayBatcher, AListReceivedIsReusedForTheNextBatch) {
    Outbox out;
    RayBatcher b(2);
    RayList received;
    received.reserve(40);
    received.resize(2);
    const RayItem* block = received.data();
    b.recycle(received);
    b.add(PosX, job(Vec3(0.0), Vec3(1, 0, 0), 0, 7), 1, out);
    b.add(PosX, job(Vec3(0.0), Vec3(1, 0, 0), 0, 8), 1, out);
    ASSERT_EQ(out.size(), 1u);
    Message& m = out[0].second;
    EXPECT_EQ(m.rayAt(0).pixel, 7u);
    EXPECT_EQ(m.rayAt(1).pixel, 8u);
    EXPECT_EQ(m.takeBatch().data(), block);  // the same heap block, emptied and filled again
}

// ---- The frame-buffer outbox (fb_outbox.h) ----

TEST(FrameBufferOutbox, ContributionsByUnitThenCreditWithTheCounts) {
    Outbox out;
    FrameBufferOutbox fb(3, 2);  // pixel p to unit p mod 3, 2 per message
    fb.setCredit(Credit(8));
    fb.add({contribution(0), contribution(4), contribution(3)}, out);  // units 0, 1, 0: unit 0's batch is full
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].first, FrameBufferOutbox::target(0));
    EXPECT_EQ(out[0].second.type, MsgType::Contributions);
    EXPECT_EQ(out[0].second.body().contributions.size(), 2u);
    EXPECT_EQ(out[0].second.bytes(), kHeaderBytes + 2 * kContributionBytes);
    EXPECT_EQ(fb.contributions(), 1u);
    EXPECT_TRUE(fb.owes());
    fb.addCredit(3);
    fb.flush(out, [] { return "n"; });
    ASSERT_EQ(out.size(), 3u);  // unit 1's part batch, then the credit to unit 0
    EXPECT_EQ(out[1].first, FrameBufferOutbox::target(1));
    EXPECT_EQ(out[1].second.body().contributions.size(), 1u);
    EXPECT_EQ(out[2].first, FrameBufferOutbox::target(0));
    EXPECT_EQ(out[2].second.type, MsgType::Credit);
    EXPECT_EQ(out[2].second.body().credit.value(), 0.125);
    const auto& counts = out[2].second.body().unitCounts;  // units but 0 since the last credit: unit 1 got 1
    ASSERT_EQ(counts.size(), 1u);
    EXPECT_EQ(counts[0], (std::pair<uint16_t, uint32_t>{1, 1}));
    EXPECT_FALSE(fb.owes());
}

TEST(FrameBufferOutbox, ContributionsWithoutCreditAreABug) {
    Outbox out;
    FrameBufferOutbox fb(2, 1);
    fb.setCredit(Credit(8));
    fb.add({contribution(1)}, out);
    EXPECT_THROW(fb.flush(out, [] { return "n"; }), std::logic_error);
}

// ---- The queue's high-water mark (queue_marks.h) ----

namespace {
struct FakeInput {  // messages arrived at these times, not taken
    std::vector<Picos> arrivals;
    size_t unconsumed() const { return arrivals.size(); }
    size_t arrivedBy(Picos t) const {
        size_t n = 0;
        for (Picos a : arrivals) n += a <= t;
        return n;
    }
};
}  // namespace

TEST(QueueDepthMarks, CountsWhatHadArrivedByEachStep) {
    size_t mark = 0;
    QueueDepthMarks q(mark);
    FakeInput in{{100, 200, 900}};
    q.step(250, 1, in);  // 1 in hand, 2 arrived by 250
    EXPECT_EQ(mark, 3u);
    q.step(50, 0, in);
    EXPECT_EQ(mark, 3u);
    q.step(950, 2, in);
    EXPECT_EQ(mark, 5u);
}

TEST(QueueDepthMarks, DeferredStepsCountTheMessagesTakenSince) {
    size_t mark = 0;
    QueueDepthMarks q(mark);
    q.defer(300, 1);    // a step at 300 beyond what the node saw, 1 in hand
    q.taken(150);       // then it took two messages that had arrived by 300
    q.taken(250);
    q.defer(400, 0);
    q.taken(390);
    FakeInput in{{310, 320}};  // and two more arrived by 400, not taken
    q.settle(in);
    // At 300: 1 + the 2 taken since (arrived by 300) + 0 arrived by 300 still there.
    // At 400: 0 + the 1 taken since + 2 arrived by 400 = 3.
    EXPECT_EQ(mark, 3u);
    size_t other = 0;
    QueueDepthMarks r(other);
    r.defer(300, 1);
    r.taken(150);
    r.taken(250);
    r.settle(FakeInput{});
    EXPECT_EQ(other, 3u);
}

// ---- Messages and the mesh's geometry ----

TEST(Messages, EachKindCarriesWhatItSaysAndWeighsItsBytes) {
    EXPECT_EQ(Message::ack(0.5).type, MsgType::Ack);
    EXPECT_EQ(Message::ack(0.5).body().boundary, 0.5);
    EXPECT_EQ(Message::ack(0.5).bytes(), kHeaderBytes + kAckBytes);
    const Message r = Message::loadReport(4, 10, 20, 30, 40, 0.5);
    EXPECT_EQ(r.type, MsgType::LoadReport);
    EXPECT_EQ(r.body().interval, 4);
    EXPECT_EQ(r.body().wait, 30u);
    EXPECT_EQ(r.bytes(), kHeaderBytes + kLoadReportBytes);
    EXPECT_EQ(Message::fbExpect(9).body().count, 9u);
    EXPECT_EQ(Message::fbExpect(9).bytes(), kHeaderBytes + kFbExpectBytes);
    EXPECT_EQ(Message::fbDone().bytes(), kHeaderBytes);
    Credit c(70);
    c.add(66);
    EXPECT_EQ(Message::credit(c, {{1, 2}, {3, 4}}).bytes(), kHeaderBytes + 24 + 2 * kUnitCountBytes);
    EXPECT_TRUE(isControl(MsgType::Slide));
    EXPECT_FALSE(isControl(MsgType::Credit));
}

TEST(MeshGeometry, NodesColumnsAndDirectionsRoundTrip) {
    const std::array<int, 3> dims{3, 4, 5};
    for (size_t i = 0; i < 60; ++i) EXPECT_EQ(nodeIndex(cellAt(i, dims), dims), i);
    for (int axis = 0; axis < 3; ++axis) {
        const ColumnGeometry g(axis, dims);
        EXPECT_EQ(g.count() * g.length(), 60);
        std::vector<int> seen(size_t(g.count()), 0);
        for (size_t i = 0; i < 60; ++i) {
            const Cell c = cellAt(i, dims);
            EXPECT_EQ(g.cell(c[g.u], c[g.v], c[axis]), c);
            ++seen[size_t(g.columnOf(c))];
        }
        for (int n : seen) EXPECT_EQ(n, g.length());  // each column holds its N nodes
    }
    for (int d = 0; d < kDirs; ++d) {
        EXPECT_EQ(dirNamed(dirName(d)), d);
        EXPECT_EQ(neighbour(neighbour(Cell{1, 1, 1}, d), opposite(d)), (Cell{1, 1, 1}));
    }
    EXPECT_FALSE(dirNamed("+w"));
    EXPECT_FALSE(inMesh(neighbour(Cell{2, 0, 0}, PosX), dims));
    EXPECT_EQ(nodeName(Cell{1, 2, 3}), "node_1_2_3");
    EXPECT_EQ(linkSuffix(NegZ), "mz");
}
