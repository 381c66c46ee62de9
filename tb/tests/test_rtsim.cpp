// rtsim end to end, as a user runs it (each run its own process): determinism
// of report, image and VCD; timing laws (doubling every cost doubles the
// render time; on a line of nodes the render time grows with latency by the
// hop count); waveforms that GTKWave's tools accept; bad configuration.
// Balancing and frames: test_rtsim_balance.cpp; stops: test_rtsim_stops.cpp;
// decoupling: test_rtsim_quantum.cpp.
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

TEST_F(Rtsim, SameInputsSameBytes) {
    const std::string args = std::string(kSmall) + " --mesh 3 --link-depth 2 --no-baseline -q";
    for (const char* k : {"a", "b"}) {
        const std::string p = (dir_ / k).string();
        ASSERT_EQ(run(args + " --image " + p + ".png --report " + p + ".json --vcd " + p + ".vcd").code, 0);
    }
    EXPECT_EQ(slurp(dir_ / "a.png"), slurp(dir_ / "b.png"));
    EXPECT_EQ(slurp(dir_ / "a.vcd"), slurp(dir_ / "b.vcd"));
    EXPECT_GT(slurp(dir_ / "a.vcd").size(), 1000u);
    json a = json::parse(slurp(dir_ / "a.json")), b = json::parse(slurp(dir_ / "b.json"));
    EXPECT_TRUE(a.contains("wall_s"));
    dropWall(a);
    dropWall(b);
    EXPECT_EQ(a, b);
    EXPECT_FALSE(a.contains("wall_s"));
    // A different seed is a different scene.
    ASSERT_EQ(run(args + " --seed 7 --image " + (dir_ / "c.png").string()).code, 0);
    EXPECT_NE(slurp(dir_ / "a.png"), slurp(dir_ / "c.png"));
}

TEST_F(Rtsim, ReportHoldsPerNodeAccounting) {
    const json r = report(std::string(kSmall) + " --mesh 2");
    ASSERT_EQ(r["nodes"].size(), 8u);
    const double render = r["render_time_ns"];
    EXPECT_GT(render, 0);
    for (const json& n : r["nodes"]) {
        for (const char* k : {"busy_ns", "wait_ns", "load", "rays_traced", "queue_high_water"}) EXPECT_TRUE(n.contains(k)) << k;
        EXPECT_NEAR(n["busy_ns"].get<double>() + n["wait_ns"].get<double>(), render, 1e-3);
        EXPECT_NEAR(n["load"].get<double>(), n["busy_ns"].get<double>() / render, 1e-12);
    }
    // 3 mesh links per node of a 2x2x2 mesh, plus its port to the frame buffer.
    EXPECT_EQ(r["links"].size(), 8u * 3 + 8);
    EXPECT_GT(r["totals"]["messages"]["ray"].get<uint64_t>(), 0u);
}

TEST_F(Rtsim, DoublingEveryCostDoublesRenderTime) {
    const std::string base = std::string(kSmall) + " --mesh 2 --link-depth 2 --fb-depth 3";
    const std::string one =
        " --cost-sphere 10ns --cost-polygon 20ns --cost-cone 20ns --cost-voxel 4ns --cost-raygen 20ns --cost-shade 50ns"
        " --cost-send 40ns --cost-recv 40ns --cost-host 5ns --link-latency 100ns --link-bandwidth 1GB/s"
        " --fb-latency 200ns --fb-bandwidth 2GB/s";
    const std::string two =
        " --cost-sphere 20ns --cost-polygon 40ns --cost-cone 40ns --cost-voxel 8ns --cost-raygen 40ns --cost-shade 100ns"
        " --cost-send 80ns --cost-recv 80ns --cost-host 10ns --link-latency 200ns --link-bandwidth 500MB/s"
        " --fb-latency 400ns --fb-bandwidth 1GB/s";
    const json a = report(base + one, "a.json"), b = report(base + two, "b.json");
    EXPECT_EQ(2 * a["render_time_ns"].get<double>(), b["render_time_ns"].get<double>());
    EXPECT_EQ(a["totals"]["messages"], b["totals"]["messages"]);
}

// --link-stats counts leaves the links' latency percentiles, high-water
// marks and windowed peaks out of the report and changes nothing else: every other field, the
// image and the VCD are the full run's, in lockstep, with a quantum past the
// lookahead, and under a balancing policy with a control lane (whose data
// messages move on the wire).
TEST_F(Rtsim, LinkCountsOnlyLeaveOutTheDistributionsAndChangeNothingElse) {
    const std::string base = std::string(kSmall) + " --mesh 3 --link-depth 2 --fb-depth 3";
    for (const char* mode : {" --quantum 0", " --quantum 10us", " --balance slide --balance-interval 20us --link-control-depth 2"}) {
        SCOPED_TRACE(mode);
        json full = report(base + mode + " --vcd " + (dir_ / "f.vcd").string(), "f.json");
        json counts = report(base + mode + " --link-stats counts --vcd " + (dir_ / "c.vcd").string(), "c.json");
        EXPECT_EQ(slurp(dir_ / "f.vcd"), slurp(dir_ / "c.vcd"));
        EXPECT_EQ(full["config"]["link_stats"], "full");
        EXPECT_EQ(counts["config"]["link_stats"], "counts");
        size_t withLatency = 0;
        for (json* j : {&full, &counts}) {
            dropWall(*j);
            j->erase("rerun");  // (the flags given)
            (*j)["config"].erase("link_stats");
            for (json& l : (*j)["links"]) {
                const bool kept = j == &full;
                EXPECT_EQ(l.contains("backlog_high_water"), kept);
                EXPECT_EQ(l.contains("buffer_high_water"), kept);
                if (!kept) {
                    EXPECT_FALSE(l.contains("latency_ns"));
                }
                EXPECT_EQ(l.contains("peak_utilisation"), kept);
                withLatency += l.erase("latency_ns") + l.erase("control_latency_ns");
                l.erase("backlog_high_water");
                l.erase("buffer_high_water");
                l.erase("peak_utilisation");
                l.erase("peak_window_ns");
            }
            for (json& l : (*j)["busiest_links"]) l.erase("peak_utilisation");
        }
        EXPECT_GT(withLatency, 0u);
        EXPECT_EQ(full, counts);
    }
}

TEST_F(Rtsim, LatencyOnALineAddsOneLatencyPerHop) {
    // One pixel, one ray: from the eye at -x through every node of a line to a
    // sphere in the last one; everything but the link latency costs nothing.
    std::ofstream(dir_ / "line.nff") << "b 0 0 0\nv\nfrom -10 0 0\nat 0 0 0\nup 0 0 1\nangle 10\nhither 1\n"
                                        "resolution 1 1\nl 100 0 0\nf 1 1 1 1 0 0 0 0\n"
                                        "s 3.5 0 0 0.5\ns -3.5 3 3 0.01\n";  // the small sphere stretches the world box to -x
    const std::string zero =
        " --cost-sphere 0ns --cost-polygon 0ns --cost-cone 0ns --cost-voxel 0ns --cost-raygen 0ns --cost-shade 0ns"
        " --cost-send 0ns --cost-recv 0ns --cost-host 0ns --link-bandwidth 1TB/s --fb-latency 1us --fb-bandwidth 1TB/s";
    for (int n = 2; n <= 4; ++n) {
        SCOPED_TRACE(n);
        const std::string args = " --scene " + (dir_ / "line.nff").string() + " --mesh-dims " + std::to_string(n) + "x1x1" + zero;
        const double t1 = report(args + " --link-latency 1us", "a.json")["render_time_ns"];
        const double t2 = report(args + " --link-latency 3us", "b.json")["render_time_ns"];
        // The ray crosses n - 1 links; each costs 2 us more.
        EXPECT_NEAR(t2 - t1, 2000.0 * (n - 1), 1e-3);
    }
}

TEST_F(Rtsim, ARaysWorkIsRecordedWhereItsSegmentRanToTheHit) {
    // One ray from the eye at -x through a 2 x 1 x 1 mesh (the plane at x =
    // 0): it hits a sphere at x = 0.3 near the front of node 1's box, which
    // runs to x = 3.51; its shadow ray goes back to the light at -x. Both
    // segments in node 1 span [0, 0.3]: the work by position centres there,
    // not at the middle of the box (1.75), where the ray would have left it.
    std::ofstream(dir_ / "front.nff") << "b 0 0 0\nv\nfrom -10 0 0\nat 0 0 0\nup 0 0 1\nangle 10\nhither 1\n"
                                         "resolution 1 1\nl -100 0 0\nf 1 1 1 1 0 0 0 0\n"
                                         "s 0.8 0 0 0.5\ns 3.5 3 3 0.01\ns -3.5 3 3 0.01\n";
    const json r = report(" --scene " + (dir_ / "front.nff").string() + " --mesh-dims 2x1x1 --axis x --balance measured", "a.json");
    const json& n = r["nodes"][1];
    ASSERT_EQ(n["node"], json::array({1, 0, 0}));
    ASSERT_GT(n["box"][1][0].get<double>(), 3.0);
    const json& w = n["work_by_position"];
    double work = 0, moment = 0;
    for (size_t k = 0; k < w["ns"].size(); ++k) {
        const double x = w["axis_from"].get<double>() + (w["first_bin"].get<double>() + k + 0.5) * w["bin_width"].get<double>();
        work += w["ns"][k].get<double>();
        moment += x * w["ns"][k].get<double>();
    }
    ASSERT_GT(work, 0);
    EXPECT_NEAR(moment / work, 0.15, w["bin_width"].get<double>()) << w.dump();
}

TEST_F(Rtsim, EachNodesGridIsTheResolutionRuleOverItsObjectsWorkedByHand) {
    // Two spheres of radius 1 at x = -2 and 2: the world is [-3, 3] x [-1, 1]^2
    // (padded by 0.01 %). The rule (sw/grid.h): over the part of its box its
    // objects occupy, k = cbrt(8 n / V) cells per unit length, each axis
    // round(extent k) cells, the part at least one cell of the whole box's
    // grid thick.
    std::ofstream(dir_ / "two.nff") << "b 0 0 0\nv\nfrom -10 0 0\nat 0 0 0\nup 0 0 1\nangle 10\nhither 1\n"
                                       "resolution 4 4\nl -100 0 0\nf 1 1 1 1 0 0 0 0\ns -2 0 0 1\ns 2 0 0 1\n";
    auto expectGrid = [](const json& n, std::array<int, 3> cells, std::array<double, 2> x) {
        SCOPED_TRACE(n["node"].dump());
        ASSERT_TRUE(n.contains("grid")) << n.dump();
        EXPECT_EQ(n["grid"]["cells"], json(cells));
        const json& span = n["grid"]["span"];
        EXPECT_NEAR(span[0][0].get<double>(), x[0], 1e-6);
        EXPECT_NEAR(span[1][0].get<double>(), x[1], 1e-6);
        for (int a = 1; a < 3; ++a) {  // the sphere's bounds across the axis
            EXPECT_NEAR(span[0][size_t(a)].get<double>(), -1, 1e-6);
            EXPECT_NEAR(span[1][size_t(a)].get<double>(), 1, 1e-6);
        }
    };
    // Two boxes, split at x = 0: node 1 holds the sphere at 2 and its part
    // is the sphere's bounds, a cube of side 2: k = cbrt(8 / 8) = 1, 2 x 2 x 2.
    const json two = report(" --scene " + (dir_ / "two.nff").string() + " --mesh-dims 2x1x1 --balance none", "two.json");
    expectGrid(two["nodes"][1], {2, 2, 2}, {1, 3});
    expectGrid(two["nodes"][0], {2, 2, 2}, {-3, -1});
    // Eight boxes, 0.75 thick: node 5 spans [0.75, 1.5] and holds the sphere
    // at 2, which reaches 0.5 into it. Its whole box's grid has round(0.75 x
    // cbrt(8 / 3)) = 1 cell along x, so the part is widened to the box's
    // thickness: [0.75, 1.5] x [-1, 1]^2, V = 3, 1 x 3 x 3 cells. A ray across
    // the box tests the sphere wherever it runs: one cell along the axis.
    const json eight = report(" --scene " + (dir_ / "two.nff").string() + " --mesh-dims 8x1x1 --balance none", "eight.json");
    const json& n5 = eight["nodes"][5];
    ASSERT_EQ(n5["objects"], 1);
    expectGrid(n5, {1, 3, 3}, {n5["box"][0][0].get<double>(), n5["box"][1][0].get<double>()});
    EXPECT_NEAR(n5["box"][0][0].get<double>(), 0.75, 1e-3);
    // A box with no objects walks no cell: no grid.
    for (const json& n : eight["nodes"]) {
        if (n["objects"] == 0) {
            EXPECT_FALSE(n.contains("grid")) << n.dump();
        }
    }
    EXPECT_EQ(eight["nodes"][3]["objects"], 0);
}

TEST_F(Rtsim, TestsOfRaysRunningAcrossTheAxisInsideABoxAreRecordedApart) {
    // One ray from the eye at -x along y = z = 0 hits the sphere at x = 2;
    // its shadow ray goes back to the light at -x. The world spans z from
    // -1.01 to 3.01: with the axis z on a 1 x 1 x 2 mesh the plane is at z =
    // 1, and both segments run inside node 0, entering and leaving by faces
    // across the axis (or ending there): every sphere test of node 0 is
    // `within`, 1 us each. With the axis x on a 2 x 1 x 1 mesh the ray
    // enters by a face along the axis: none is.
    std::ofstream(dir_ / "across.nff") << "b 0 0 0\nv\nfrom -10 0 0\nat 0 0 0\nup 0 0 1\nangle 10\nhither 1\n"
                                          "resolution 1 1\nl -100 0 0\nf 1 1 1 1 0 0 0 0\n"
                                          "s 2 0 0 0.5\ns 3.5 3 3 0.01\ns -3.5 -3 -1 0.01\n";
    const std::string scene = " --scene " + (dir_ / "across.nff").string() + " --balance measured --cost-sphere 1us";
    const json across = report(scene + " --mesh-dims 1x1x2 --axis z", "across.json");
    const json& n0 = across["nodes"][0];
    ASSERT_EQ(n0["node"], json::array({0, 0, 0}));
    const double tests = n0["counters"]["intersection_tests_by_primitive"]["sphere"].get<double>();
    ASSERT_GE(tests, 2);  // the ray's and its shadow ray's
    auto within = [](const json& n) {  // ns of its `within` bins (none: 0)
        double w = 0;
        if (n["work_by_position"].contains("within"))
            for (const json& v : n["work_by_position"]["within"]["ns"]) w += v.get<double>();
        return w;
    };
    ASSERT_TRUE(n0["work_by_position"].contains("within")) << n0["work_by_position"].dump();
    EXPECT_NEAR(within(n0), 1000 * tests, 1e-6);
    const json along = report(scene + " --mesh-dims 2x1x1 --axis x", "along.json");
    for (const json& n : along["nodes"]) EXPECT_EQ(within(n), 0) << n.dump();
}

TEST_F(Rtsim, WaveformsConvertAndGroupPerNode) {
    const std::string vcd = (dir_ / "w.vcd").string();
    ASSERT_EQ(run(std::string(kSmall) + " --mesh 2 --no-baseline -q --image '' --vcd " + vcd).code, 0);
    const std::string text = slurp(vcd);
    for (const char* s : {"$timescale 1ps $end", "node_1_1_1", "busy", "wait", "$var real 64", "queue"})
        EXPECT_NE(text.find(s), std::string::npos) << s;
    EXPECT_EQ(text.find("$date"), std::string::npos);  // nothing that changes between runs
    const std::string gtkw = slurp(dir_ / "w.gtkw");
    EXPECT_NE(gtkw.find("[dumpfile] \"w.vcd\""), std::string::npos);
    EXPECT_NE(gtkw.find("@800200\n-node_0_0_0"), std::string::npos);
    EXPECT_NE(gtkw.find("machine.node_1_0_1.busy"), std::string::npos);
    const std::string cmd = "vcd2fst -v " + vcd + " -f " + (dir_ / "w.fst").string() + " >" + (dir_ / "v2f").string() + " 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(dir_ / "v2f");
    EXPECT_GT(fs::file_size(dir_ / "w.fst"), 0u);
}

// The waveforms against the report, from outside the run's own
// accounting: each node's busy and wait signals, integrated over the frame
// from the VCD's value changes, give the report's busy and wait times to
// the picosecond; with balancing steps and with nodes blocked on full
// output buffers too. Each link's `wire` integrates to its wire busy time,
// and its `backlog` (messages sent, not yet on the wire) to the time its
// messages waited for a slot and for the wire.
TEST_F(Rtsim, BusyAndWaitIntegratedFromTheVcdAreTheReports) {
    for (const char* extra : {"", " --balance slide --balance-interval 2us", " --fb-units 2 --fb-depth 1 --fb-out-depth 1",
                              " --balance slide --balance-interval 2us --link-control-depth 2"}) {  // (links recording late)
        SCOPED_TRACE(extra);
        const fs::path vcd = dir_ / "i.vcd", rep = dir_ / "i.json";
        const Outcome o = run(std::string(kSmall) + " --mesh 2 --link-depth 2 --no-baseline -q --image '' --vcd " +
                              vcd.string() + " --report " + rep.string() + extra);
        ASSERT_EQ(o.code, 0) << o.err;
        const json r = json::parse(slurp(rep));
        const auto end = uint64_t(std::llround(r["render_time_ns"].get<double>() * 1000));
        // Every bit and integer signal: its scope below `machine` joined
        // with '_' (node_0_0_0, node_0_0_0_px) and name; its integral.
        std::map<std::string, std::pair<std::string, std::string>> signal;  // code -> (scope, name)
        std::map<std::string, uint64_t> value, since, integral;
        std::istringstream in(slurp(vcd));
        std::string line;
        std::vector<std::string> scopes;
        uint64_t now = 0;
        auto change = [&](const std::string& code, uint64_t v) {
            if (!signal.count(code)) return;
            integral[code] += value[code] * (now - since[code]);
            value[code] = v;
            since[code] = now;
        };
        while (std::getline(in, line)) {
            std::istringstream w(line);
            std::string a, b, c, d, e;
            w >> a >> b >> c >> d >> e;
            if (a == "$scope") scopes.push_back(c);
            else if (a == "$upscope") scopes.pop_back();
            else if (a == "$var" && (b == "wire" || b == "integer")) {
                std::string path;
                for (size_t k = 1; k < scopes.size(); ++k) path += (k > 1 ? "_" : "") + scopes[k];
                signal[d] = {path, e};
            } else if (!line.empty() && line[0] == '#') now = std::stoull(line.substr(1));
            else if (!line.empty() && (line[0] == '0' || line[0] == '1')) change(line.substr(1), uint64_t(line[0] - '0'));
            else if (!line.empty() && line[0] == 'b') change(b, std::stoull(a.substr(1), nullptr, 2));
        }
        now = end;
        for (const auto& [code, v] : value) change(code, v);  // to the end
        std::map<std::pair<std::string, std::string>, uint64_t> by;  // (scope, name) -> integral
        for (const auto& [code, what] : signal) by[what] = integral[code];
        auto at = [&](const std::string& scope, const std::string& name) { return by.count(std::make_pair(scope, name)) ? by[std::make_pair(scope, name)] : ~uint64_t(0); };
        size_t checked = 0;
        for (const json& n : r["nodes"]) {
            const std::string name = "node_" + std::to_string(n["node"][0].get<int>()) + "_" +
                                     std::to_string(n["node"][1].get<int>()) + "_" + std::to_string(n["node"][2].get<int>());
            for (const char* k : {"busy", "wait"}) {
                EXPECT_EQ(at(name, k), uint64_t(std::llround(n[std::string(k) + "_ns"].get<double>() * 1000))) << name << " " << k;
                ++checked;
            }
        }
        EXPECT_EQ(checked, 2 * r["nodes"].size());
        uint64_t waited = 0;
        for (const json& l : r["links"]) {
            const std::string name = l["name"];
            EXPECT_EQ(at(name, "wire"), uint64_t(std::llround(l["wire_busy_ns"].get<double>() * 1000))) << name;
            const double w = l["slot_wait_ns"].get<double>() + l["wire_wait_ns"].get<double>();
            EXPECT_EQ(at(name, "backlog"), uint64_t(std::llround(w * 1000))) << name;
            waited += at(name, "backlog");
        }
        EXPECT_GT(waited, 0u);  // (depth-2 links: messages did wait)
    }
}

// --trace-nodes busiest:K traces what a first pass found held the frame
// back: the K nodes with the most busy time and the K links busy longest
// with a backlog. Tracing changes no timing, so the traced run's own report
// ranks them the same way; the VCD holds those nodes' scopes and no other.
TEST_F(Rtsim, TraceBusiestTracesWhatItsOwnReportRanksFirst) {
    // One frame; and the last of a sequence, its first pass by the sequence's machine.
    for (const std::string extra : {"", " --frames 3 --balance slide --balance-interval 5us"}) {
        SCOPED_TRACE(extra);
        const fs::path vcd = dir_ / "b.vcd";
        const json r = report(std::string(kSmall) + " --mesh 3 --link-bandwidth 200MB/s --trace-nodes busiest:2 --vcd " +
                              vcd.string() + extra, "b.json");
        const json& chosen = r["trace_busiest"];
        ASSERT_EQ(chosen["k"], 2);
        std::vector<std::pair<double, json>> nodes;
        for (const json& n : r["nodes"]) nodes.push_back({n["busy_ns"].get<double>(), n["node"]});
        std::stable_sort(nodes.begin(), nodes.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
        EXPECT_EQ(chosen["nodes"], json::array({nodes[0].second, nodes[1].second}));
        ASSERT_EQ(chosen["links"].size(), 2u);
        // The links: the report's own busiest_links, which rank the same way.
        for (size_t i = 0; i < 2; ++i) {
            const json& l = chosen["links"][i];
            const json& n = l["node"];
            const std::string name = "node_" + std::to_string(n[0].get<int>()) + "_" + std::to_string(n[1].get<int>()) + "_" +
                                     std::to_string(n[2].get<int>()) + "_" +
                                     (l["dir"] == "fb" ? std::string("fb") : std::string(l["dir"].get<std::string>()[0] == '+' ? "p" : "m") + l["dir"].get<std::string>()[1]);
            EXPECT_EQ(name, r["busiest_links"][i]["name"]) << i;
        }
        EXPECT_GT(r["busiest_links"][0]["saturated_ns"].get<double>(), 0.0);
        const std::string text = slurp(vcd);
        size_t scopes = 0;
        for (size_t at = text.find("$scope module node_"); at != std::string::npos; at = text.find("$scope module node_", at + 1)) ++scopes;
        EXPECT_LE(scopes, 4u);  // the two nodes, and the senders of links traced without their node
        for (const auto& [busy, cell] : nodes)
            if (busy < nodes[1].first && text.find("module node_" + std::to_string(cell[0].get<int>()) + "_" +
                                                   std::to_string(cell[1].get<int>()) + "_" + std::to_string(cell[2].get<int>()) +
                                                   " $end\n$var wire 1") != std::string::npos)
                ADD_FAILURE() << "a node not chosen has its busy signal traced: " << cell;
        for (const char* bad : {"busiest:0", "busiest:65", "busiest:x"}) {
            const Outcome o = run(std::string(kSmall) + " --mesh 2 --no-baseline -q --image '' --trace-nodes " + bad);
            EXPECT_EQ(o.code, 2) << bad;
            EXPECT_NE(o.err.find("busiest:K with K in 1..64"), std::string::npos) << o.err;
        }
        const Outcome both = run(std::string(kSmall) + " --mesh 2 --no-baseline -q --image '' --trace-nodes busiest --trace-nodes 0,0,0");
        EXPECT_EQ(both.code, 2);
    }
}

TEST_F(Rtsim, TraceSubsetAndWindow) {
    const std::string vcd = (dir_ / "s.vcd").string();
    ASSERT_EQ(run(std::string(kSmall) + " --mesh 2 --no-baseline -q --image '' --vcd " + vcd +
                  " --trace-nodes 1,0,0 --trace-nodes 0,1,1 --trace-window 2us,5us")
                  .code,
              0);
    const std::string text = slurp(vcd);
    EXPECT_NE(text.find("node_1_0_0"), std::string::npos);
    EXPECT_NE(text.find("node_0_1_1"), std::string::npos);
    EXPECT_EQ(text.find("node_0_0_0"), std::string::npos);
    // Every timestamp lies in the window.
    std::istringstream in(text);
    std::string line;
    int stamps = 0;
    while (std::getline(in, line))
        if (!line.empty() && line[0] == '#') {
            const double t = std::stod(line.substr(1));
            EXPECT_GE(t, 2e6);
            EXPECT_LE(t, 5e6);
            ++stamps;
        }
    EXPECT_GT(stamps, 1);
    // A window after the frame's end: the VCD of nothing, and a warning that says so (it was silent).
    const Outcome late = run(std::string(kSmall) + " --mesh 2 --no-baseline -q --image '' --vcd " + vcd + " --trace-window 1s,2s");
    EXPECT_EQ(late.code, 0);
    EXPECT_NE(late.err.find("warning: --trace-window: starts at 1 s, after the frame ended at "), std::string::npos) << late.err;
    EXPECT_EQ(std::count(late.err.begin(), late.err.end(), '\n'), 1) << late.err;
    EXPECT_EQ(slurp(vcd).find("\n#"), std::string::npos);
    EXPECT_EQ(run(std::string(kSmall) + " --mesh 2 --no-baseline -q --image '' --vcd " + vcd + " --trace-window 2us,5us").err, "");
}

TEST_F(Rtsim, DefaultRunPrintsSummaryWithSpeedup) {
    ASSERT_EQ(run("--spheres 100 --size 24x24 --image " + (dir_ / "d.png").string()).code, 0);
    const Outcome o = run("--spheres 100 --size 24x24 --image " + (dir_ / "d.png").string());
    for (const char* s : {"4x4x4 mesh", "render time", "speed-up", "busy per node", "wait per node", "messages", "busiest links", "wall clock"})
        EXPECT_NE(o.out.find(s), std::string::npos) << s << "\n" << o.out;
}

// Without flags both programs render the built-in scene, the same one
// (rtref's was f = 1, rtsim's f = 1/4: two images, both "procedural (1000 objects)").
TEST_F(Rtsim, RtsimAndRtrefWithoutFlagsRenderTheSameImage) {
    ASSERT_EQ(std::system((std::string(RTREF_EXE) + " -o " + (dir_ / "ref.png").string() + " >/dev/null").c_str()), 0);
    const Outcome o = run(" --no-baseline -q --image " + (dir_ / "sim.png").string());
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_EQ(slurp(dir_ / "ref.png"), slurp(dir_ / "sim.png"));
}

// The speed-up's baseline (the same frame on one node, run by rtsim as a
// child) against a computation of its own: one node does every operation
// rtref counts for the frame, at the costs given, and sends its
// contributions in full batches of 32, then the last part batch and its
// credit in one step; with one host that costs nothing per contribution
// and a port of 1 ps per message, the frame ends one latency and two wire
// picoseconds after that last step.
TEST_F(Rtsim, TheSpeedupsBaselineIsTheOneNodeFrameByHand) {
    const std::string scene = " --spheres 200 --radius 0.04 --concentration 0.5 --size 32x32";  // (rtsim: f = 1/N unless given)
    ASSERT_EQ(std::system((std::string(RTREF_EXE) + scene + " -o " + (dir_ / "ref.png").string() + " --stats " +
                           (dir_ / "ref.json").string() + " >/dev/null")
                              .c_str()),
              0);
    const json ref = json::parse(slurp(dir_ / "ref.json"));
    const Outcome o = run(scene + " --mesh 3 --fb-units 1 --cost-host 0 --fb-latency 300ns --fb-bandwidth 1000TB/s"
                                  " --cost-sphere 11ns --cost-voxel 3ns --cost-raygen 17ns --cost-shade 19ns --cost-send 23ns"
                                  " --image '' --report " + (dir_ / "r.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json r = json::parse(slurp(dir_ / "r.json"));
    const uint64_t misses = r["totals"]["primary_misses"];  // filled in by the host, at no cost
    const uint64_t primaries = ref["primary_rays"].get<uint64_t>() - misses;
    const uint64_t contributions = ref["contributions"].get<uint64_t>() - misses;
    ASSERT_NE(contributions % 32, 0u);  // a part batch at the end
    const uint64_t messages = contributions / 32 + 1 + 1;
    const double last = 11.0 * ref["intersection_tests_by_primitive"]["sphere"].get<double>() +
                        3.0 * ref["voxel_steps"].get<double>() + 17.0 * double(primaries) +
                        19.0 * ref["shadings"].get<double>() + 23.0 * double(messages);
    const double expected = last + 300.0 + 0.002;
    EXPECT_DOUBLE_EQ(r["baseline"]["render_time_ns"].get<double>(), expected);
    EXPECT_DOUBLE_EQ(r["baseline"]["speedup"].get<double>(), expected / r["render_time_ns"].get<double>());
}
// The presets: modern.conf is exactly the built-in defaults, and the 1987
// preset is a valid configuration that changes every cost.
TEST_F(Rtsim, PresetsAreValidAndModernIsTheDefault) {
    json a = report(std::string(kSmall) + " --mesh 2 --config " RT_CONFIG_DIR "/modern.conf", "a.json");
    json b = report(std::string(kSmall) + " --mesh 2", "b.json");
    dropWall(a);
    dropWall(b);
    a.erase("rerun");  // (the flags given differ: that is the point)
    b.erase("rerun");
    EXPECT_TRUE(a == b) << json::diff(b, a).dump().substr(0, 800);
    const json t = report(std::string(kSmall) + " --mesh 2 --config " RT_CONFIG_DIR "/transputer-1987.conf", "t.json");
    EXPECT_EQ(t["config"]["costs"]["test_sphere_ns"].get<double>(), 17000.0);
    EXPECT_EQ(t["config"]["link"]["latency_ns"].get<double>(), 1500.0);
    EXPECT_GT(t["render_time_ns"].get<double>(), 1000 * b["render_time_ns"].get<double>());
}

// A traced run's report keeps its trace flags, not its --vcd: run again
// without one, it traces nothing and says nothing; a trace flag typed
// after --rerun without --vcd is refused as on any command line.
TEST_F(Rtsim, RerunOfATracedRunNeedsNoVcd) {
    const std::string rep = (dir_ / "traced.json").string();
    ASSERT_EQ(run(std::string(kSmall) + " --mesh 2 --no-baseline -q --image '' --trace-nodes 1,0,0 --vcd " +
                  (dir_ / "t.vcd").string() + " --report " + rep)
                  .code,
              0);
    const Outcome again = run("--rerun " + rep + " -q --image ''");
    EXPECT_EQ(again.code, 0) << again.err;
    EXPECT_EQ(again.err, "");
    expectBad("--rerun " + rep + " -q --image '' --trace-window 0,1us", "--trace-window: says what the VCD traces");
}

// A reference run shares its parent's stderr: its messages say whose they
// are, so that its stop or error does not read as the parent's.
TEST_F(Rtsim, AReferenceRunSaysItIsOne) {
    const Outcome baseline = run(std::string(kSmall) + " --mesh 0 --as-baseline -q --image ''");
    EXPECT_EQ(baseline.code, 2);
    EXPECT_EQ(baseline.err.rfind("rtsim (its baseline run): error: --mesh", 0), 0u) << baseline.err;
    const Outcome comparison = run(std::string(kSmall) + " --mesh 0 --as-comparison -q --image ''");
    EXPECT_EQ(comparison.err.rfind("rtsim (its comparison run): error: --mesh", 0), 0u) << comparison.err;
    EXPECT_EQ(run(std::string(kSmall) + " --mesh 0 -q --image ''").err.rfind("rtsim: error: --mesh", 0), 0u);
}

TEST_F(Rtsim, ConfigFileGivesEveryFlag) {
    std::ofstream(dir_ / "c.ini") << "mesh = 2\nspheres = 150\nsize = \"20x20\"\nlink-latency = \"250ns\"\n";
    const json r = report("--config " + (dir_ / "c.ini").string());
    EXPECT_EQ(r["config"]["mesh"], json({2, 2, 2}));
    EXPECT_EQ(r["config"]["link"]["latency_ns"].get<double>(), 250.0);
    EXPECT_EQ(r["config"]["image"], json({20, 20}));
}

TEST_F(Rtsim, BadConfigurationExits2NamingTheFlag) {
    expectBad("--mesh 0", "--mesh");
    expectBad("--mesh 33", "--mesh");
    expectBad("--mesh-dims 64x64x9", "--mesh-dims");
    expectBad("--link-latency -5ns", "--link-latency");
    expectBad("--link-latency 5", "--link-latency");
    expectBad("--link-bandwidth 0GB/s", "--link-bandwidth");
    expectBad("--link-bandwidth fast", "--link-bandwidth");
    expectBad("--link-depth 0", "--link-depth");
    expectBad("--link-out-depth -1", "--link-out-depth");
    expectBad("--fb-out-depth many", "--fb-out-depth");
    expectBad("--link-set 0,0,0,+x:out_depth=-2", "out_depth");
    expectBad("--link-set 0,0,0,+x:control_depth=x", "control_depth");
    expectBad("--scene /nonexistent.nff", "--scene");
    expectBad("--frobnicate", "--frobnicate");
    expectBad("--mesh-dims 2x2", "--mesh-dims");
    expectBad("--node-speed 9,9,9=2", "--node-speed");
    expectBad("--node-speed 0,0,0=-1", "--node-speed");
    expectBad("--link-set 3,3,3,+x:latency=1us", "--link-set");
    expectBad("--trace-window 5us", "--trace-window");
    expectBad("--trace-links 1,1", "--trace-links");
    expectBad("--trace-links 0,0,0,+w", "--trace-links");
    expectBad("--mesh 2 --trace-links 5,0,0", "--trace-links: node outside the mesh");
    expectBad("--mesh 2 --trace-links 1,0,0,+x", "--trace-links: no link in that direction");
    // Typed without --vcd they would trace nothing (a --rerun of a traced run carries them: RerunOfATracedRunNeedsNoVcd).
    expectBad("--mesh 2 --trace-nodes 0,0,0", "--trace-nodes: says what the VCD traces, but no --vcd is given");
    expectBad("--mesh 2 --trace-links 0,0,0,+x", "--trace-links: says what the VCD traces");
    expectBad("--trace-window 0,5us", "--trace-window: says what the VCD traces");
    expectBad("--trace-nodes busiest", "--trace-nodes: says what the VCD traces");
    expectBad("--map /nonexistent/m.png", "--map: /nonexistent/m.png");
    expectBad("--quantum soon", "--quantum");
    expectBad("--guard-wire -0.5", "--guard-wire");
    expectBad("--guard-wire busy", "--guard-wire");
    expectBad("--fb-units 0", "--fb-units");
    expectBad("--fb-units 257", "--fb-units");
    expectBad("--balance sometimes", "--balance");
    // `default` meant the recommended policy while the default of --balance was none: one name each now.
    expectBad("--balance default", "--balance: 'default' names no policy: the recommended policy is sample on columns of "
                                   "2 to 8 boxes, measured on longer ones, none on columns of one box (or 'recommended')");
    // (a flag the policy --balance recommended chose does not take: the error says it chose it, and why)
    expectBad("--mesh-dims 4x4x1 --axis z --balance recommended --start-mix 0.5",
              "--start-mix 0.5: only median and sample start at a split of their own; 'none' (--balance recommended's "
              "choice: columns of 1 box: no boundary along the axis to move) starts at the uniform split");
    expectBad("--mesh-dims 9x1x1 --balance recommended --sample-end credit",
              "--sample-end credit: only sample gathers a sample, not 'measured' (--balance recommended's choice: columns "
              "of 9 boxes (more than 8): the first frame keeps its split)");
    expectBad("--balance slide --polish-tries 3",
              "--polish-tries: only resplit, measured and sample polish the planes they hold between frames, not 'slide'");
    expectBad("--mesh-dims 4x4x1 --axis z --balance recommended --frames 3 --polish-tries 2",
              "--polish-tries: only resplit, measured and sample polish the planes they hold between frames, not 'none' "
              "(--balance recommended's choice: columns of 1 box: no boundary along the axis to move)");
    expectBad("--eye nan,0,0", "--eye");
    expectBad("--seed -1", "--seed");  // (was taken as 18446744073709551615)
    expectBad("--light 1,nan,1", "--light");
    expectBad("--eye 1e200,0.5,0.5", "--eye: expected a number of magnitude at most 1e9");  // (ran, background only, exit 0)
    expectBad("--look-at 0,0,1e10", "--look-at: expected a number of magnitude at most 1e9");
    // CLI11 reads integers in C's base 0: --mesh 010 ran 8x8x8, 0x10 16x16x16.
    expectBad("--mesh 010", "--mesh: expected a decimal integer, got '010' (a leading 0");
    expectBad("--mesh 08", "--mesh: expected a decimal integer, got '08' (a leading 0");  // said "not in range 1 to 32"
    expectBad("--spheres 0x10", "--spheres: expected a decimal integer, got '0x10'");
    expectBad("--seed 00", "--seed: expected a decimal integer");
    // And strtod's hexadecimal in times, rates and numbers: 0x10ns was 16 ns, --speed 0x10 16.
    expectBad("--link-latency 0x10ns", "--link-latency");
    expectBad("--link-bandwidth 0x1p30B/s", "--link-bandwidth");
    expectBad("--max-error 0x1%", "--max-error");
    expectBad("--speed 0x10", "--speed: expected a decimal number, got '0x10'");
    expectBad("--seed 18446744073709551616", "--seed: above 18446744073709551615");  // (was taken as 2^64 - 1)
    // The report keeps every flag, in JSON: a value that is not UTF-8 (a
    // file's name may be any bytes) is refused before the run, naming its
    // flag (it failed as the report was written, exit 1, naming none).
    {
        const std::string bytes = (dir_ / "\xff.nff").string();
        std::ofstream(bytes) << "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.01\nresolution 8 8\ns 0 0 0 1\n";
        expectBad("--scene " + bytes, "--scene: \"" + (dir_ / "\xef\xbf\xbd.nff").string() + "\" is not valid UTF-8");
        std::ofstream(dir_ / "bytes.ini") << "scene = " << bytes << "\n";
        expectBad("--config " + (dir_ / "bytes.ini").string(), "bytes.ini:1: --scene: ");
    }
    expectBad("--eye-step 0,inf,0 --frames 2", "--eye-step");
    expectBad("--eye-step 1 --frames 2", "--eye-step: expected three numbers");  // (was read past its end)
    expectBad("--eye-step 1,2 --frames 2", "--eye-step: expected three numbers");
    // More than three: CLI11 kept the last three (--eye 1,2,3,4 ran from 2,3,4), on the command line or in a file.
    expectBad("--eye 1,2,3,4", "--eye: expected three numbers x y z (or x,y,z), got 4");
    expectBad("--look-at 0.5,0.5 0.5,0.5", "--look-at: expected three numbers x y z (or x,y,z), got 4");
    expectBad("--eye-step 1,2,3,4 --frames 2", "--eye-step: expected three numbers");
    // "--flag=" with nothing after it: CLI11 took the next argument as its value
    // (--sample-links= --mesh 2 said "got '--mesh'"; --image= --size 8x8 named the image "--size").
    expectBad("--balance sample --sample-links= --mesh 2", "--sample-links: nothing after '=' in '--sample-links='");
    expectBad("--image= --size 8x8", "--image: nothing after '=' in '--image=': write --image VALUE (an empty value: --image '')");
    std::ofstream(dir_ / "eye.ini") << "eye = [1, 2, 3, 4]\n";
    expectBad("--config " + (dir_ / "eye.ini").string(), "eye.ini:1: --eye: expected three numbers");
    // A camera path onto the point looked at, or along `up`: each frame's view checked first
    // (they rendered a flat background, or nothing, with exit 0).
    expectBad("--size 16x16 --mesh 2 --frames 3 --eye-step 0,1.05,0", "--eye-step: frame 3's eye (0.5, 0.5, 0.5) is the point looked at");
    expectBad("--size 16x16 --mesh 2 --frames 2 --eye-step 0,2.1,-1", "frame 2's eye (0.5, 0.5, -0.5) looks along the view's up vector");
    std::ofstream(dir_ / "bad.ini") << "mesh = [not closed\n";
    expectBad("--config " + (dir_ / "bad.ini").string(), "");
    std::ofstream(dir_ / "bad2.ini") << "no-such-flag = 3\n";
    expectBad("--config " + (dir_ / "bad2.ini").string(), "no-such-flag");
    std::ofstream(dir_ / "short.ini") << "q\n";  // (it said "argument was not expected: --q=true")
    expectBad("--config " + (dir_ / "short.ini").string(), "short.ini:1: 'q' is the short -q: a file names a flag by its long name, quiet");
    expectBad("--config /nonexistent.ini", "/nonexistent.ini");
    expectBad("--config /dev/urandom", "/dev/urandom");  // read whole, it never ended
    expectBad("--boundaries-from /dev/urandom", "--boundaries-from: not a regular file");
    expectBad("--size 65536x65536", "--size 65536x65536: needs at least");  // was bad_alloc, naming nothing
    // A size the user never typed is named as the scene's (it said "--size 65536x65536").
    std::ofstream(dir_ / "huge.nff") << "v\nfrom 0 0 -5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 65536 65536\n"
                                        "s 0 0 0 1\n";
    expectBad("--scene " + (dir_ / "huge.nff").string(), "the scene's resolution 65536x65536 (--size sets another): needs at least");
    // Times the picosecond counter cannot hold: 1e6 s once rendered 1.8e16 ns.
    expectBad("--link-latency 1e6s", "--link-latency");
    expectBad("--cost-sphere 1000.5s", "--cost-sphere");
    expectBad("--balance-interval 1e20s", "--balance-interval");
    expectBad("--balance slide --balance-interval 1ps", "--balance-interval: 1 ps is shorter");  // ran 20 s, then bad_alloc
    expectBad("--balance slide --balance-interval 79ns", "--balance-interval");  // cost-send + cost-recv: 80 ns
    // Outputs that cannot be written: exit 2 before the run, and nothing
    // left behind (the image is not written when the report cannot be).
    expectBad("--image /nonexistent/x.png", "--image: /nonexistent/x.png: no such folder");
    expectBad("--report " + dir_.string(), "--report: " + dir_.string() + ": is a folder");
    expectBad("--vcd /proc/x.vcd", "--vcd: /proc/x.vcd");
    expectBad("--image " + (dir_ / "x.png").string() + " --report /nonexistent/r.json", "--report");
    EXPECT_FALSE(fs::exists(dir_ / "x.png"));
    std::ofstream(dir_ / "big.ini") << std::string(2 << 20, '#');
    expectBad("--config " + (dir_ / "big.ini").string(), "big.ini");
}

TEST_F(Rtsim, ARunPastThePicosecondCounterStopsWithAnError) {
    // Each cost within the limit (1,000 s), but a few thousand sphere tests
    // of 1,000 s each pass 2^62 ps: one line naming the node, no report.
    const Outcome o = run(" --size 64x64 --mesh 2 --cost-sphere 1000s --no-baseline --image '' --report " +
                          (dir_ / "r.json").string());
    EXPECT_EQ(o.code, 1);
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
    EXPECT_NE(o.err.find("simulated time past"), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("machine.node_"), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(dir_ / "r.json"));
    EXPECT_EQ(run(" --size 2x2 --mesh 2 --cost-sphere 1000s -q --no-baseline --image ''").code, 0)
        << "a short run at the same costs stays within the counter";
}


// An output buffer as deep as the most messages any link ever held waiting
// in the unbounded run never fills: the same run, to the picosecond.
TEST_F(Rtsim, AnOutputBufferThatNeverFillsChangesNothing) {
    const std::string args = std::string(kSmall) + " --mesh 3 --link-depth 2 --no-baseline -q --image ''";
    ASSERT_EQ(run(args + " --report " + (dir_ / "free.json").string()).code, 0);
    const json free = json::parse(slurp(dir_ / "free.json"));
    size_t deepest = 0;
    for (const json& l : free["links"])
        if (l["to"] != "fb") deepest = std::max(deepest, l["backlog_high_water"].get<size_t>());
    ASSERT_GT(deepest, 1u);  // messages did wait: a buffer of 1 would have blocked
    const Outcome o = run(args + " --link-out-depth " + std::to_string(deepest) + " --report " + (dir_ / "deep.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json deep = json::parse(slurp(dir_ / "deep.json"));
    EXPECT_EQ(deep["render_time_ns"], free["render_time_ns"]);
    EXPECT_EQ(deep["totals"]["blocked_ns"].get<double>(), 0.0);
    for (size_t i = 0; i < free["nodes"].size(); ++i) {
        EXPECT_EQ(deep["nodes"][i]["busy_ns"], free["nodes"][i]["busy_ns"]);
        EXPECT_EQ(deep["nodes"][i]["wait_ns"], free["nodes"][i]["wait_ns"]);
    }
}

// --primary-order spread from the command line: echoed in the report and
// named in the summary's first line (a row-by-row run says nothing), the
// same image, another render time; and a rerun of its report runs it again.
TEST_F(Rtsim, SpreadPrimaryOrderIsEchoedSaidAndRerun) {
    const std::string args = "--spheres 200 --size 32x32 --mesh 3";
    const nlohmann::json scan = reportWithImage(args + " -q --no-baseline", "scan.png");
    const nlohmann::json spread = reportWithImage(args + " -q --no-baseline --primary-order spread", "spread.png");
    EXPECT_EQ(scan["config"]["primary_order"], "scan");
    EXPECT_EQ(spread["config"]["primary_order"], "spread");
    EXPECT_EQ(slurp(dir_ / "scan.png"), slurp(dir_ / "spread.png"));
    EXPECT_NE(scan["render_time_ns"], spread["render_time_ns"]);
    const std::string said = ", primary rays spread (--primary-order spread)";
    EXPECT_NE(run(args + " --no-baseline --image '' --primary-order spread").out.find(said), std::string::npos);
    EXPECT_EQ(run(args + " --no-baseline --image ''").out.find(said), std::string::npos);
    const std::string path = (dir_ / "spread.json").string();
    ASSERT_EQ(run(args + " -q --no-baseline --image '' --primary-order spread --report " + path).code, 0);
    const nlohmann::json again = report("--rerun " + path, "again.json");
    EXPECT_EQ(again["render_time_ns"], spread["render_time_ns"]);
}
