// The frame buffer (models/framebuffer/frame_buffer.*), held to things outside the model:
// the reference renderer's image and its contributions (every one
// accumulated exactly once, in the unit that holds its pixel), and the end
// of the frame and back-pressure against closed forms worked out here by
// hand. Also the render-time bounds (models/analysis/bounds.*).
#include <random>

#include <gtest/gtest.h>

#include "analysis/bounds.h"
#include "machine/machine.h"
#include "renderer.h"
#include "scenes.h"

using namespace rt;

namespace {

// What each unit must hold, from the reference renderer: per unit (pixel
// mod K) the number of contributions and their digest.
struct Expected {
    std::vector<uint64_t> count, digest;
};
Expected expectedPerUnit(const Scene& s, int width, int height, int units) {
    RenderOptions ro;
    ro.width = width;
    ro.height = height;
    Expected e{std::vector<uint64_t>(size_t(units), 0), std::vector<uint64_t>(size_t(units), 0)};
    for (const Contribution& c : referenceContributions(s, ro)) {
        ++e.count[c.pixel % uint32_t(units)];
        e.digest[c.pixel % uint32_t(units)] += contributionDigest(c);
    }
    return e;
}

void expectConserved(const MachineResult& r, const Expected& e) {
    ASSERT_EQ(r.frameBuffer.size(), e.count.size());
    for (size_t u = 0; u < e.count.size(); ++u) {
        SCOPED_TRACE("unit " + std::to_string(u));
        const FrameBufferStats& s = r.frameBuffer[u].stats;
        EXPECT_EQ(s.contributions + s.own, e.count[u]);
        EXPECT_EQ(s.digest, e.digest[u]);
    }
}

struct Case {
    int units, n;
    std::string policy;
    int lane = 0;  // control-lane slots on every link (0: none)
};
void PrintTo(const Case& c, std::ostream* os) {
    *os << c.units << " units, N=" << c.n << ", " << c.policy << (c.lane ? ", lane" : "");
}

// Random link, port, batch and cost settings, fixed by the case.
MachineConfig randomized(const Case& k) {
    std::mt19937_64 rng(uint64_t(7919 * k.units + 31 * k.n + uint64_t(k.policy[0])));
    MachineConfig c;
    const int n = k.n;
    c.dims = {n, n, n};
    c.width = c.height = 20;
    c.fbUnits = k.units;
    c.fbPort = LinkParams{Picos(1000 + rng() % 1000000), 1e7 * double(1 + rng() % 300), int(1 + rng() % 3)};
    c.fbBatch = int(1 + rng() % 40);
    c.hostCost = Picos(rng() % 200000);
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                for (int d = 0; d < kDirs; ++d) {
                    Cell m{x, y, z};
                    m[dirAxis(d)] += dirStep(d);
                    if (m[dirAxis(d)] < 0 || m[dirAxis(d)] >= n) continue;
                    if (rng() % 2)
                        c.linkOverride[{{x, y, z}, d}] =
                            LinkParams{Picos(1000 + rng() % 500000), 1e7 * double(1 + rng() % 1000), int(1 + rng() % 3),
                                       k.lane};
                }
    c.link.controlDepth = k.lane;
    c.balance.policy = k.policy;
    c.balance.interval = 3000000;  // 3 us: frames of tens of us see boundaries move
    c.balance.gain = 1.0;
    return c;
}

}  // namespace

class FrameBufferIdentity : public testing::TestWithParam<Case> {};

TEST_P(FrameBufferIdentity, ImageMatchesReferenceAndEveryContributionIsAccumulatedOnce) {
    const Scene s = test::procedural();
    const MachineConfig cfg = randomized(GetParam());
    const MachineResult r = runMachine(s, cfg);
    RenderOptions ro;
    ro.width = cfg.width;
    ro.height = cfg.height;
    EXPECT_TRUE(r.image == render(s, Partition::whole(s), ro).image);
    expectConserved(r, expectedPerUnit(s, cfg.width, cfg.height, cfg.fbUnits));
    // The frame ends after the last accumulation anywhere.
    for (const FrameBufferUnitReport& u : r.frameBuffer) EXPECT_LE(u.stats.lastActive, r.renderTime);
}

static std::vector<Case> identityCases() {
    std::vector<Case> v;
    for (int units : {1, 3, 16})
        for (int n = 1; n <= 8; ++n)
            for (const char* p : {"none", "slide", "work", "quantile", "median"}) v.push_back({units, n, p});
    // With the control lane on every link: at these random link speeds the
    // reports alone can fill a slow link's wire, and before the lanes took
    // turns on it (link.h) a ray behind them waited for ever (16 units, N = 7,
    // work and quantile, never ended).
    for (int n = 2; n <= 8; ++n)
        for (const char* p : {"slide", "work", "quantile"}) v.push_back({16, n, p, 2});
    return v;
}

INSTANTIATE_TEST_SUITE_P(All, FrameBufferIdentity, testing::ValuesIn(identityCases()),
                         [](const testing::TestParamInfo<Case>& i) {
                             return std::to_string(i.param.units) + "units_N" + std::to_string(i.param.n) + "_" +
                                    i.param.policy + (i.param.lane ? "_lane" : "");
                         });

// ---- The end of the frame and back-pressure, against closed forms ----
//
// One node whose operations cost nothing: it makes every contribution and
// sends it (one per message) at time 0, then one credit message to unit 0.
// A port's wire takes 1 ps per message (bandwidth 10^15 B/s: the 1 ps floor)
// and L of latency. Unit u accumulates C_u contributions at h each.
namespace {

constexpr Picos kL = 300000;  // port latency, 300 ns
constexpr Picos kWire = 1;    // any message on the wire

struct EndOfFrame {
    MachineResult result;
    std::vector<uint64_t> c;  // C_u, from the reference renderer
};

// How the kernel is kept in step: lockstep, or each process running ahead
// by its lookahead with the units other than 0 taking their input as it
// comes (late 0), up to 10 us late (the default) or up to a second late
// (after the whole frame). The simulated times are the same in each.
struct Timing {
    bool lookahead;
    Picos late;
};
const Timing kTimings[] = {{false, 0}, {true, 0}, {true, 10000000}, {true, 1000000000000}};

std::string describe(const Timing& t) {
    return t.lookahead ? "lookahead, units late by up to " + std::to_string(t.late) + " ps" : "lockstep";
}

EndOfFrame oneNodeRun(const Timing& timing, int units, Picos h, int depth, double bandwidth = 1e15, int batch = 1,
                      Picos latency = kL) {
    ProceduralParams p;
    p.spheres = 60;
    p.radius = 0.08;
    p.angle = 30;  // every primary ray enters the world box: no background made by the host itself
    const Scene s = makeProceduralScene(p);
    MachineConfig c;
    c.dims = {1, 1, 1};
    c.width = c.height = 12;
    c.costs.test = {0, 0, 0};
    c.costs.voxelStep = c.costs.rayGen = c.costs.shade = c.costs.send = c.costs.recv = 0;
    c.fbUnits = units;
    c.fbPort = LinkParams{latency, bandwidth, depth};
    c.fbBatch = batch;
    c.hostCost = h;
    c.lookaheadQuantum = timing.lookahead;
    c.fbLate = timing.late;
    EndOfFrame e{runMachine(s, c), expectedPerUnit(s, c.width, c.height, units).count};
    for (const FrameBufferUnitReport& u : e.result.frameBuffer) EXPECT_EQ(u.stats.own, 0u);
    for (uint64_t n : e.c) EXPECT_GT(n, 0u);  // every unit gets work (the forms below assume it)
    return e;
}

}  // namespace

// Parameters: the number of units, and the timing (kTimings).
class EndOfFrameClosedForm : public testing::TestWithParam<std::tuple<int, int>> {
protected:
    int units() const { return std::get<0>(GetParam()); }
    const Timing& timing() const { return kTimings[std::get<1>(GetParam())]; }
};

// Deep ports (16) and slow units (h = 1 us > 2L / 15): each unit is never
// starved, so it finishes at F_u = L + 1 + C_u h. Unit 0 takes the credit
// right after its own contributions, T_0 = F_0, and sends fb_expect, which
// reaches unit u at A = T_0 + L + 1; u answers at max(F_u, A), and unit 0
// has the answer L + 1 later.
TEST_P(EndOfFrameClosedForm, UnitBoundFrame) {
    const int units = this->units();
    const Picos h = 1000000;
    SCOPED_TRACE(describe(timing()));
    const EndOfFrame e = oneNodeRun(timing(), units, h, 16);
    auto finish = [&](size_t u) { return kL + kWire + e.c[u] * h; };
    Picos expected = finish(0);
    for (size_t u = 1; u < e.c.size(); ++u)
        expected = std::max(expected, std::max(finish(u), finish(0) + kL + kWire) + kL + kWire);
    EXPECT_EQ(e.result.renderTime, expected);
    for (size_t u = 0; u < e.c.size(); ++u) {
        EXPECT_EQ(e.result.frameBuffer[u].stats.busy, e.c[u] * h);
        EXPECT_EQ(e.result.frameBuffer[u].stats.lastActive, finish(u));
    }
}

// Depth-1 ports and fast units (h = 100 ns < 2L + 1): the port is the limit.
// A slot comes back L after its message is taken, so messages reach unit u
// 2L + 1 apart: message i is taken at L + 1 + i (2L + 1), and u finishes at
// F_u = L + 1 + (C_u - 1)(2L + 1) + h. The credit is message C_0 on unit
// 0's port: T_0 = L + 1 + C_0 (2L + 1). The rest as above.
TEST_P(EndOfFrameClosedForm, PortBoundFrameWithDepthOnePorts) {
    const int units = this->units();
    const Picos h = 100000, gap = 2 * kL + kWire;
    SCOPED_TRACE(describe(timing()));
    const EndOfFrame e = oneNodeRun(timing(), units, h, 1);
    const Picos t0 = kL + kWire + e.c[0] * gap;
    Picos expected = t0;
    for (size_t u = 1; u < e.c.size(); ++u) {
        const Picos f = kL + kWire + (e.c[u] - 1) * gap + h;
        EXPECT_EQ(e.result.frameBuffer[u].stats.lastActive, f);
        expected = std::max(expected, std::max(f, t0 + kL + kWire) + kL + kWire);
    }
    EXPECT_EQ(e.result.renderTime, expected);
    // Back-pressure: messages waited in the node's backlog for a slot.
    size_t backlog = 0;
    for (const LinkReport& l : e.result.links)
        if (l.dir < 0) backlog = std::max(backlog, l.stats().backlogHighWater);
    EXPECT_GT(backlog, 1u);
}

// The same end of the frame with the messages' real sizes on the wire: at
// 1 GB/s a message takes its size in bytes as ns. Written by hand: a
// contribution message 8 + 40 bytes; the credit message 8 + 8 (a lone node
// is handed the whole credit, 1: only the whole-part word is sent) + 6 per
// other unit it sent contributions to; fb_expect 8 + 8; fb_done 8.
// Units are fast (h = 1 ns) and ports deep (1,000 slots, never short), so
// each port's wire is the limit: message k reaches unit u at 48 (k + 1) + L.
// Unit u is done at F_u = 48 C_u + L + h; the credit reaches unit 0 at
// T_0 = 48 C_0 + (16 + 6 (K - 1)) + L; fb_expect reaches unit u at
// T_0 + 16 + L, and its fb_done is at unit 0 8 + L after max(F_u, that).
// With L = 5 us the handshake, not the units, sets the end: every term of
// it counts.
class HandshakeClosedForm : public EndOfFrameClosedForm {};

TEST_P(HandshakeClosedForm, WireBoundFrameWithRealMessageSizes) {
    const int units = this->units();
    const Picos h = 1000, ns = 1000, L = 5000 * ns;
    SCOPED_TRACE(describe(timing()));
    const EndOfFrame e = oneNodeRun(timing(), units, h, 1000, 1e9, 1, L);
    const Picos t0 = (48 * e.c[0] + 16 + 6 * Picos(units - 1)) * ns + L;
    Picos expected = t0;
    bool handshakeBound = false;
    for (size_t u = 1; u < e.c.size(); ++u) {
        const Picos f = 48 * e.c[u] * ns + L + h;
        handshakeBound |= t0 + 16 * ns + L > f;
        expected = std::max(expected, std::max(f, t0 + 16 * ns + L) + 8 * ns + L);
    }
    EXPECT_TRUE(handshakeBound);  // the case this test is for
    EXPECT_EQ(e.result.renderTime, expected);
}

// A unit's busy time is its contributions times the cost, however they are
// batched into messages.
TEST_P(EndOfFrameClosedForm, BusyIsPerContributionWhateverTheBatch) {
    const int units = this->units();
    const Picos h = 1000000;
    const EndOfFrame e = oneNodeRun(timing(), units, h, 16, 1e15, 4);
    for (size_t u = 0; u < e.c.size(); ++u) EXPECT_EQ(e.result.frameBuffer[u].stats.busy, e.c[u] * h);
}

INSTANTIATE_TEST_SUITE_P(Units, EndOfFrameClosedForm,
                         testing::Combine(testing::Values(1, 2, 5, 16), testing::Range(0, int(std::size(kTimings)))));
INSTANTIATE_TEST_SUITE_P(Units, HandshakeClosedForm,  // one unit has no handshake
                         testing::Combine(testing::Values(2, 5, 16), testing::Range(0, int(std::size(kTimings)))));

// ---- The bounds, from figures written here ----

TEST(Bounds, PerfectColumnAndFrameBufferByHand) {
    MachineConfig c;
    c.dims = {2, 2, 1};
    c.balance.axis = 0;  // columns along x: cells that share y and z
    MachineResult r;
    r.renderTime = 1000;
    r.cells = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    r.nodes.resize(4);
    const Picos busy[] = {100, 500, 300, 340};  // column y=0: 600, column y=1: 640
    for (int i = 0; i < 4; ++i) r.nodes[size_t(i)].busy = busy[i];
    r.frameBuffer.resize(3);
    r.frameBuffer[0].stats.busy = 70;
    r.frameBuffer[1].stats.busy = 90;
    r.frameBuffer[2].stats.busy = 20;
    const Bounds b = renderTimeBounds(r, c);
    EXPECT_EQ(b.perfect, 1240u / 4);
    EXPECT_EQ(b.column, 640u / 2);
    EXPECT_EQ(b.frameBuffer, 90u);
    c.balance.axis = 1;  // columns along y: cells that share x and z; x=0: 400, x=1: 840
    EXPECT_EQ(renderTimeBounds(r, c).column, 840u / 2);
}
