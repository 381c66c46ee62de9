// The links on their own: the queues they are built on, the latency
// histogram, the occupation and lookahead, and the control lane, against
// values worked out by hand (no machine run).
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
#include "base/radix_heap.h"
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
// The express relay's queue (base/radix_heap.h) against a multiset: its
// top is always the least time queued, times pushed after a pop may be
// below the top but not below the time popped, every item of the least
// time comes out at once, and none is lost; with times from 0 to 2^63 so
// that every digit's buckets are used, the last digit's (bits 60 to 63) too.
TEST(RadixHeap, TopAndTiesAreTheLeastTimesQueuedAsItemsComeAndGo) {
    std::mt19937_64 rng(7);
    RadixHeap<uint32_t> heap;
    std::multiset<std::pair<uint64_t, uint32_t>> ref;
    uint64_t last = 0;
    uint32_t next = 0;
    std::vector<uint32_t> ties;
    for (int round = 0; round < 4000; ++round) {
        const int pushes = int(rng() % 4);
        for (int i = 0; i < pushes; ++i) {
            const int bits = int(rng() % 64);  // spans of every size past the last popped
            const uint64_t span = bits == 0 ? 0 : rng() >> (64 - bits);
            const uint64_t t = last + std::min(span, (uint64_t(1) << 63) - last);
            heap.push(t, next);
            ref.insert({t, next++});
        }
        if (round % 500 == 0 && last > 0) {
            EXPECT_THROW(heap.push(last - 1, 0), std::logic_error);
        }
        ASSERT_EQ(heap.size(), ref.size());
        if (ref.empty()) continue;
        ASSERT_EQ(heap.top(), ref.begin()->first) << round;
        if (rng() % 3 == 0) continue;  // (a top asked for and not popped: later pushes may be below it)
        ties.clear();
        heap.popTies(ties);
        last = ref.begin()->first;
        std::vector<uint32_t> want;
        while (!ref.empty() && ref.begin()->first == last) {
            want.push_back(ref.begin()->second);
            ref.erase(ref.begin());
        }
        std::sort(ties.begin(), ties.end());
        ASSERT_EQ(ties, want) << round;
    }
    EXPECT_GT(next, 5000u);
}

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

// A ray of `sample`'s sample under --sample-end credit (Message::priority)
// takes the control lane as a load report does. 1 byte/ns, 100 ns latency:
// two ray messages of 1,000 bytes at t = 0 take the wire at 0 and 1000 ns;
// the sample's ray (132 bytes) sent at 500 ns goes on when the first
// leaves (1000), ahead of the second, which moves back by 132 ns. The same
// ray without the mark waits behind both.
TEST(ControlLane, ASampleRayGoesAheadOfWaitingRaysByHand) {
    for (bool priority : {true, false}) {
        Link l("l", oneBytePerNs(2));
        for (int i = 0; i < 2; ++i) l.send(rays(8), 0);
        Message s = rays(1);
        s.priority = priority;
        l.send(std::move(s), 500 * ns);
        EXPECT_EQ(l.consume(1100 * ns).type, MsgType::Ray);  // the first ray message: 1000 + 100
        if (priority) {
            EXPECT_FALSE(l.controlArrivedBy(1231 * ns));
            ASSERT_TRUE(l.controlArrivedBy(1232 * ns));  // 1000 + 132 + 100
            EXPECT_EQ(l.consumeControl(1232 * ns).rayCount(), 1u);
            EXPECT_THROW(l.consume(2231 * ns), std::logic_error);  // the second: 1132 + 1000 + 100
            EXPECT_EQ(l.consume(2232 * ns).rayCount(), 8u);
        } else {
            EXPECT_FALSE(l.controlArrivedBy(1000000 * ns));
            EXPECT_EQ(l.consume(2100 * ns).rayCount(), 8u);
            EXPECT_THROW(l.consume(2231 * ns), std::logic_error);  // 2000 + 132 + 100
            EXPECT_EQ(l.consume(2232 * ns).rayCount(), 1u);
        }
    }
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

// A link adds what it measured of each message it delivered to its figures
// a batch at a time (Link::foldTaken), not at each take. The figures must be
// those counted one take at a time: a link whose figures are read after
// every take (each read folds) against one read only at the frame's end,
// on the same random traffic of rays and load reports over both lanes,
// with few slots so that messages wait for slots and for the wire, and
// control messages go ahead of waiting rays (the union of the wire waits,
// `saturated`, is counted in the order of the takes across the lanes).
TEST(Link, FiguresGainedABatchAtATimeAreThoseCountedTakeByTake) {
    for (int controlSlots : {0, 1, 2})
        for (unsigned seed = 1; seed <= 6; ++seed) {
            LinkParams p{100 * ns, 1e9, 3};
            p.controlDepth = controlSlots;
            Link eachTake("each", p, smallestMeshMessage(true)), atEnd("end", p, smallestMeshMessage(true));
            std::mt19937 rng(seed);
            Picos t = 0;
            uint64_t sent = 0, taken = 0;
            for (int step = 0; step < 3000; ++step) {
                t += Picos(rng() % 300) * ns / 2;
                const unsigned what = rng() % 8;
                if (what < 3) {  // a ray message of 1 to 4 rays
                    const int k = 1 + int(rng() % 4);
                    eachTake.send(rays(k), t);
                    atEnd.send(rays(k), t);
                    ++sent;
                } else if (what < 4) {
                    eachTake.send(report(), t);
                    atEnd.send(report(), t);
                    ++sent;
                } else {  // the receiver takes what has arrived: a control message first, now and then
                    const bool control = what == 4 && eachTake.controlArrivedBy(t);
                    Picos a = 0;
                    if (!control && !(eachTake.peekArrival(a) && a <= t)) continue;
                    const Message m1 = control ? eachTake.consumeControl(t) : eachTake.consume(t);
                    const Message m2 = control ? atEnd.consumeControl(t) : atEnd.consume(t);
                    ASSERT_EQ(m1.type, m2.type);
                    ++taken;
                    (void)eachTake.stats();  // (folds)
                }
            }
            ASSERT_GT(taken, 500u);
            ASSERT_GT(sent - taken, 0u);  // some left at the frame's end, their waits counted up to it
            eachTake.endFrame(t);
            atEnd.endFrame(t);
            const LinkStats a = eachTake.stats(), b = atEnd.stats();
            const std::string at = "control slots " + std::to_string(controlSlots) + ", seed " + std::to_string(seed);
            EXPECT_EQ(a.consumed, taken) << at;
            EXPECT_EQ(b.consumed, a.consumed) << at;
            EXPECT_GT(a.slotWait, 0u) << at;  // (the traffic made messages wait for slots)
            EXPECT_EQ(b.slotWait, a.slotWait) << at;
            EXPECT_EQ(b.wireWait, a.wireWait) << at;
            EXPECT_GT(a.saturated, 0u) << at;
            EXPECT_EQ(b.saturated, a.saturated) << at;
            EXPECT_EQ(b.backlogHighWater, a.backlogHighWater) << at;
            EXPECT_EQ(b.bufferHighWater, a.bufferHighWater) << at;
            EXPECT_EQ(b.windows.width(), a.windows.width()) << at;
            EXPECT_EQ(b.windows.busy(), a.windows.busy()) << at;
            for (const auto& [ha, hb] : {std::pair{&a.latency, &b.latency}, std::pair{&a.controlLatency, &b.controlLatency}}) {
                EXPECT_EQ(hb->count(), ha->count()) << at;
                EXPECT_EQ(hb->bins(), ha->bins()) << at;
                EXPECT_EQ(hb->max(), ha->max()) << at;
                for (double q : {0.0, 0.25, 0.5, 0.9, 1.0}) EXPECT_EQ(hb->percentile(q), ha->percentile(q)) << at << ", " << q;
            }
            EXPECT_EQ(a.latency.count() + a.controlLatency.count(), taken) << at;
        }
}
