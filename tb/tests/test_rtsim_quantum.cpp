// rtsim end to end under temporal decoupling: up to the lookahead a
// quantum changes nothing, to the picosecond.
#include <algorithm>
#include <cmath>
#include <map>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "rtsim_test.h"

using nlohmann::json;
using namespace rt::test;

namespace {
// Temporal decoupling: a process may run ahead of the kernel by the
// quantum. Up to its lookahead (the soonest a message not yet sent can
// reach it: its input links' latency plus the smallest message's time on
// their wire) nothing changes: same report, waveforms and image as in
// lockstep. `lookahead`: the smallest process's, in ns, written by hand for
// these links (200 ns, 1 GB/s; frame-buffer ports 300 ns), and `with40`
// with one link at 40 ns.
class RtsimQuantum : public Rtsim {
protected:
    void expectExactUpToTheLookahead(const std::string& extra, double lookahead, double with40);
};
}  // namespace

// A node's lookahead: 200 ns and a ray message's 132 bytes at 1 GB/s
// (332 ns); a unit's: 300 ns and an 8-byte header (308 ns), the smallest.
// With a 40 ns link, its receiver's: 40 + 132 ns.
TEST_F(RtsimQuantum, QuantumUpToTheLinkLatencyIsExactToThePicosecond) { expectExactUpToTheLookahead("", 308, 172); }

// Nodes that block on full output buffers (here the frame-buffer ports':
// one slot, one message of buffer) block for the same picoseconds. (The
// units' links to each other: 300 ns and a header, as the ports.)
TEST_F(RtsimQuantum, BlockingOnFullOutputBuffersIsExactUpToTheLookahead) {
    expectExactUpToTheLookahead(" --fb-units 2 --fb-depth 1 --fb-out-depth 1", 308, 172);
}

// A node that blocks records its queue (the messages arrived by then) with
// the blocked state, at the end of the step that filled the buffer, which
// may lie beyond what it may run ahead to; so the kernel catches up first.
// Without that, the node recorded a queue that lacked messages not yet sent
// (4 against 6 at one node on balls-4 at 128x128, in lockstep too; here, a
// difference from lockstep).
TEST_F(RtsimQuantum, ABlockedNodeRecordsItsWholeQueue) {
    const std::string args = " --scene " + scene("balls-3") + " --size 64x64 --mesh 3 --link-out-depth 2000 --fb-out-depth 1" +
                             " --fb-depth 1 --no-baseline -q --image '' --report " + (dir_ / "r.json").string();
    ASSERT_EQ(run(args + " --quantum 0 --vcd " + (dir_ / "e.vcd").string()).code, 0);
    const json exact = json::parse(slurp(dir_ / "r.json"));
    ASSERT_GT(exact["totals"]["blocked_ns"].get<double>(), 0.0);
    ASSERT_EQ(run(args + " --vcd " + (dir_ / "q.vcd").string()).code, 0);
    EXPECT_EQ(json::parse(slurp(dir_ / "r.json"))["render_time_ns"], exact["render_time_ns"]);
    EXPECT_TRUE(slurp(dir_ / "q.vcd") == slurp(dir_ / "e.vcd"));
}

// Links and ports with no latency at all: a process's lookahead is then the
// smallest message's time on its wire alone, 8 ns here (a unit's header at
// 1 GB/s); with a control lane, a node's is the latency itself, 0 (lookahead
// mode runs in lockstep). Either way the lookahead run, traced or not (an
// untraced node without a dynamic policy runs ahead), is the lockstep run:
// the whole report, the image and the waveforms.
//
// With the default costs (4 to 50 ns each) a quantum 50 ns past the
// lookahead still gave lockstep's report; with 1 ns costs it does not (its
// links' figures differ), so there the comparison itself would see a
// lookahead 50 ns too long, not only the lookahead's figure.
TEST_F(RtsimQuantum, ZeroLatencyIsExactInLookaheadMode) {
    const std::string cheap = " --cost-send 1ns --cost-recv 1ns --cost-sphere 1ns --cost-voxel 1ns --cost-shade 1ns"
                              " --cost-raygen 1ns --cost-host 1ns";
    struct Case {
        std::string extra;
        double lookahead;
        const char* past;  // a quantum past the lookahead whose report must differ ("": not checked)
    };
    for (const auto& [extra, lookahead, past] : std::vector<Case>{
             {"", 8, ""},
             {cheap, 8, "58ns"},
             {" --balance slide --balance-interval 2us", 8, ""},
             {" --balance slide --balance-interval 2us --link-control-depth 2", 0, ""}}) {
        SCOPED_TRACE(extra);
        const std::string args = std::string(kSmall) + " --mesh 3 --link-latency 0ns --fb-latency 0ns --link-depth 2" +
                                 extra + " -q --no-baseline";
        auto runTo = [&](const std::string& name, const std::string& quantum, bool traced) {
            const Outcome o = run(args + (traced ? " --vcd " + (dir_ / (name + ".vcd")).string() : "") + " --quantum " +
                                  quantum + " --image " + (dir_ / (name + ".png")).string() + " --report " +
                                  (dir_ / (name + ".json")).string());
            EXPECT_EQ(o.code, 0) << o.err;
            json r = json::parse(slurp(dir_ / (name + ".json")));
            if (quantum == "0" || quantum == "lookahead") {
                EXPECT_EQ(r["config"]["quantum_ns"], quantum == "0" ? 0 : lookahead);
            }
            for (const char* k : {"kernel", "config", "rerun"}) r.erase(k);
            dropWall(r);
            return r;
        };
        const json exact = runTo("e", "0", true);
        if (extra.find("balance") != std::string::npos) {
            EXPECT_GT(exact["balance"]["slides"].get<int>(), 0);
        }
        for (const bool traced : {true, false}) {
            SCOPED_TRACE(traced ? "traced" : "untraced");
            const json ahead = runTo("q", "lookahead", traced);
            EXPECT_TRUE(ahead == exact) << json::diff(exact, ahead).dump().substr(0, 800);
            EXPECT_TRUE(slurp(dir_ / "q.png") == slurp(dir_ / "e.png"));
            if (traced) {
                EXPECT_TRUE(slurp(dir_ / "q.vcd") == slurp(dir_ / "e.vcd"));
            }
        }
        if (*past) {
            EXPECT_FALSE(runTo("p", past, false) == exact);
        }
    }
}

// With a dynamic policy the mesh links also carry load reports, slides
// and acks; the smallest, an ack of 16 bytes, sets a node's lookahead:
// 200 + 16 ns (40 + 16 on the 40 ns link). The slides come at the same
// picoseconds.
TEST_F(RtsimQuantum, BalancingIsExactUpToTheLookahead) {
    expectExactUpToTheLookahead(" --balance slide --balance-interval 2us", 216, 56);
}

void RtsimQuantum::expectExactUpToTheLookahead(const std::string& extra, double lookahead, double with40) {
    const bool blocking = extra.find("out-depth") != std::string::npos, balancing = extra.find("balance") != std::string::npos;
    const std::string args = std::string(kSmall) + " --mesh 3 --link-latency 200ns --fb-latency 300ns --link-depth 2" + extra;
    Outcome o = run(args + " -q --no-baseline --quantum 0 --image " + (dir_ / "e.png").string() + " --report " +
                    (dir_ / "e.json").string() + " --vcd " + (dir_ / "e.vcd").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json exact = json::parse(slurp(dir_ / "e.json"));
    // Untraced, a node running ahead in lookahead mode without a dynamic
    // policy reads its input only when it must (NodeParams::runAhead); a
    // traced one, at every step, as before.
    for (const auto& [q, traced] : std::vector<std::pair<const char*, bool>>{
             {"50ns", true}, {"200ns", true}, {"lookahead", true}, {"lookahead", false}}) {
        SCOPED_TRACE(std::string(q) + (traced ? ", traced" : ""));
        o = run(args + " -q --no-baseline --quantum " + q + " --image " + (dir_ / "q.png").string() + " --report " +
                (dir_ / "q.json").string() + (traced ? " --vcd " + (dir_ / "q.vcd").string() : ""));
        ASSERT_EQ(o.code, 0) << o.err;
        const json r = json::parse(slurp(dir_ / "q.json"));
        EXPECT_EQ(r["render_time_ns"], exact["render_time_ns"]);
        for (size_t i = 0; i < r["nodes"].size(); ++i) EXPECT_EQ(r["nodes"][i]["busy_ns"], exact["nodes"][i]["busy_ns"]);
        if (blocking) {
            EXPECT_GT(exact["totals"]["blocked_ns"].get<double>(), 0.0);  // (compared below with the rest)
        }
        if (balancing) {
            EXPECT_GT(exact["balance"]["slides"].get<int>(), 0);
        }
        // Link high-water marks are kept in simulated time, so decoupling
        // does not change them either.
        size_t waited = 0;
        for (size_t i = 0; i < r["links"].size(); ++i) {
            EXPECT_EQ(r["links"][i]["backlog_high_water"], exact["links"][i]["backlog_high_water"]) << i;
            EXPECT_EQ(r["links"][i]["buffer_high_water"], exact["links"][i]["buffer_high_water"]) << i;
            waited += r["links"][i]["backlog_high_water"].get<size_t>();
        }
        EXPECT_GT(waited, 0u);  // depth-2 links: messages did wait
        EXPECT_EQ(slurp(dir_ / "q.png"), slurp(dir_ / "e.png"));
        EXPECT_LT(r["kernel"]["delta_cycles"].get<uint64_t>(), exact["kernel"]["delta_cycles"].get<uint64_t>());
        // Everything else in the report too: queue depths, message counts.
        json a = r, b = exact;
        for (json* j : {&a, &b}) {
            j->erase("kernel");
            dropWall(*j);
            j->erase("config");
            j->erase("rerun");
        }
        EXPECT_TRUE(a == b) << json::diff(b, a).dump().substr(0, 800);
        // And the waveforms: every node's busy, wait and queue changes at the
        // same picoseconds, also where a process waits from ahead of the
        // kernel and the queue depth is traced once it has caught up.
        if (traced) {
            EXPECT_TRUE(slurp(dir_ / "q.vcd") == slurp(dir_ / "e.vcd"));
        }
        if (std::string(q) == "lookahead") {  // each process its own; the report gives the smallest
            EXPECT_EQ(r["config"]["quantum_ns"], lookahead);
            EXPECT_EQ(r["config"]["quantum"], "lookahead");
        }
    }
    // The default is the lookahead: here a 40 ns link sets the smallest
    // (node 2,1,1's, the link's receiver).
    o = run(args + " --link-set 1,1,1,+x:latency=40ns -q --no-baseline --image '' --report " + (dir_ / "d.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_EQ(json::parse(slurp(dir_ / "d.json"))["config"]["quantum_ns"], with40);
    // Beyond the lookahead the timing may drift; the image may not.
    o = run(args + " -q --no-baseline --quantum 20us --image " + (dir_ / "f.png").string() + " --report " + (dir_ / "f.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_EQ(slurp(dir_ / "f.png"), slurp(dir_ / "e.png"));
    const double drift = json::parse(slurp(dir_ / "f.json"))["render_time_ns"].get<double>() / exact["render_time_ns"].get<double>();
    // (Blocking drifts much further: a node ahead of the kernel sends, and
    // so blocks, at its local time; 1.84 here, on a 36 us frame. doc/machine.md.)
    if (!blocking && !balancing) {
        EXPECT_NEAR(drift, 1.0, 0.25);
    }
}
