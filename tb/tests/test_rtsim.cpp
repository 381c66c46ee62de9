// rtsim end to end, as a user runs it (each run its own process): determinism
// of report, image and VCD; timing laws (doubling every cost doubles the
// render time; on a line of nodes the render time grows with latency by the
// hop count); waveforms that GTKWave's tools accept; bad configuration.
#include <algorithm>
#include <cmath>
#include <map>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "command_test.h"

using nlohmann::json;
using namespace rt::test;

namespace {

// Removes wall-clock fields (their names contain "wall") everywhere.
void dropWall(json& j) {
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end();) {
            if (it.key().find("wall") != std::string::npos) it = j.erase(it);
            else dropWall(*it++);
        }
    } else if (j.is_array()) {
        for (auto& e : j) dropWall(e);
    }
}

// Six frames of resplit past the links' knee (--link-bandwidth `bandwidth`),
// and the same frame unbalanced: each frame's render time and slides.
struct ResplitAgainstNone {
    std::vector<double> ns;
    std::vector<int> slides;
    double last, none;
};

class Rtsim : public CommandTest {
protected:
    Rtsim() : CommandTest(RTSIM_EXE) {}
    json report(const std::string& args, const std::string& name = "r.json") {
        const Outcome o = run(args + " -q --no-baseline --image '' --report " + (dir_ / name).string());
        EXPECT_EQ(o.code, 0) << o.err;
        return json::parse(slurp(dir_ / name));
    }
    // Defined with the resplit tests below.
    // A procedural scene and mesh (`scene`: by default 300 spheres spread evenly, 3x3x3).
    ResplitAgainstNone resplitAgainstNone(const std::string& bandwidth,
                                          const std::string& scene = " --spheres 300 --radius 0.03 --concentration 1 --mesh 3");
};

const char* kSmall = " --spheres 200 --radius 0.04 --size 32x32";

}  // namespace

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
    const fs::path vcd = dir_ / "b.vcd";
    const json r = report(std::string(kSmall) + " --mesh 3 --link-bandwidth 200MB/s --trace-nodes busiest:2 --vcd " +
                          vcd.string(), "b.json");
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
}

TEST_F(Rtsim, DefaultRunPrintsSummaryWithSpeedup) {
    ASSERT_EQ(run("--spheres 100 --size 24x24 --image " + (dir_ / "d.png").string()).code, 0);
    const Outcome o = run("--spheres 100 --size 24x24 --image " + (dir_ / "d.png").string());
    for (const char* s : {"4x4x4 mesh", "render time", "speed-up", "busy per node", "wait per node", "messages", "busiest links", "wall clock"})
        EXPECT_NE(o.out.find(s), std::string::npos) << s << "\n" << o.out;
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

// The main job's comparison: the same frame balanced and not, each checked
// against a run of its own, and the speed-up against a run on one node.
TEST_F(Rtsim, SummaryComparesTheFrameWithAndWithoutBalancing) {
    const std::string args = std::string(kSmall) + " --mesh 3 --balance-interval 3us";
    const Outcome o = run(args + " --image '' --report " + (dir_ / "m.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json m = json::parse(slurp(dir_ / "m.json"));
    const double none = report(args + " --balance none", "n.json")["render_time_ns"];
    const json slide = report(args + " --balance slide", "s.json");
    const json noneReport = json::parse(slurp(dir_ / "n.json"));
    const double one = report(args + " --mesh 1", "o.json")["render_time_ns"];
    ASSERT_TRUE(m.contains("comparison"));
    const json& c = m["comparison"];
    EXPECT_EQ(c["balanced_policy"], "measured");  // the recommended policy (--balance recommended)
    // One frame of resplit is one frame of slide; one frame of measured
    // keeps the starting split: the unbalanced frame, to the picosecond.
    EXPECT_EQ(report(args + " --balance resplit", "r.json")["render_time_ns"], slide["render_time_ns"]);
    const json measured = report(args + " --balance measured", "d.json");
    EXPECT_EQ(measured["render_time_ns"].get<double>(), none);
    EXPECT_EQ(measured["balance"]["slides"], 0);
    EXPECT_GT(slide["balance"]["slides"].get<int>(), 0);
    // So a single frame is compared with the default's second frame: re-split from where the first measured the work.
    const double second = report(args + " --balance measured --frames 2", "d2.json")["render_time_ns"];
    EXPECT_LT(second, none);
    EXPECT_EQ(c["balanced_frame"], 2);
    EXPECT_EQ(c["unbalanced_ns"].get<double>(), none);
    EXPECT_EQ(c["balanced_ns"].get<double>(), second);
    EXPECT_DOUBLE_EQ(c["ratio"].get<double>(), second / none);
    EXPECT_EQ(c["column_bound"], noneReport["bounds"]["column"]["fraction"]);
    EXPECT_DOUBLE_EQ(m["baseline"]["speedup"].get<double>(), one / none);
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "ratio %.2f", c["ratio"].get<double>());
    EXPECT_NE(o.out.find(ratio), std::string::npos) << o.out;
    EXPECT_NE(o.out.find("frame buffer     16 units"), std::string::npos) << o.out;
    // A balancing run compares itself with the frame unbalanced, and prints its bounds.
    const Outcome b = run(args + " --balance work --image '' --report " + (dir_ / "w.json").string());
    ASSERT_EQ(b.code, 0) << b.err;
    const json w = json::parse(slurp(dir_ / "w.json"));
    EXPECT_EQ(w["comparison"]["balanced_policy"], "work");
    EXPECT_EQ(w["comparison"]["unbalanced_ns"].get<double>(), none);
    EXPECT_NE(b.out.find("bounds           of this balanced frame: perfect"), std::string::npos) << b.out;
    // Its two column bounds say whose they are: this balanced frame's, the unbalanced frame's.
    EXPECT_NE(b.out.find("the unbalanced frame's heaviest column along x"), std::string::npos) << b.out;
    // An unbalanced run names its comparison's policy as the recommended one.
    EXPECT_NE(o.out.find("this run: no balancing (none); the comparison run: balancing with measured (the recommended "
                         "policy), frame 2"), std::string::npos) << o.out;
}

// Issue 11: where the paper's rule used to lose (a frame 2.6 times longer
// with 3 us links; 0.3 GB/s links; spheres everywhere; the view across the
// axis), slide with its guard loses at most 2 %: the summary's ratio
// time(balanced) / time(none) is at most 1 / 0.98; so does the default,
// whose first frame does not slide. Without the guard the 3 us case loses
// far more, so the guard is what slide's hold.
struct Hurt {
    const char* name;
    const char* flags;
};
class NeverHurts : public Rtsim, public testing::WithParamInterface<Hurt> {};

TEST_P(NeverHurts, DefaultPolicyLosesAtMostTwoPercent) {
    // The default keeps its first frame's split (measured); slide, the
    // paper's rule within a frame, is held there by its guard.
    for (const char* policy : {"recommended", "slide"}) {
        SCOPED_TRACE(policy);
        const std::string along = " --eye=-1.3,0.5,0.5 --look-at=0.5,0.5,0.5 --fov 50";
        const std::string flags = std::string(" --size 128x128 --balance ") + policy + " " + GetParam().flags;
        const std::string args = (std::string(GetParam().name) == "view_across" ? "" : along) + flags;
        const Outcome o = run(args + " -q --image '' --report " + (dir_ / "r.json").string());
        ASSERT_EQ(o.code, 0) << o.err;
        const json r = json::parse(slurp(dir_ / "r.json"));
        EXPECT_LE(r["comparison"]["ratio"].get<double>(), 1 / 0.98) << r["comparison"].dump();
    }
}

// The same cases in steady state: the fourth frame of the default policy
// (measured) against the fourth frame without balancing, and no frame of
// the sequence slower than the first (the unbalanced frame) by 2 %.
TEST_P(NeverHurts, DefaultPolicyInSteadyStateLosesAtMostTwoPercent) {
    const std::string along = " --eye=-1.3,0.5,0.5 --look-at=0.5,0.5,0.5 --fov 50";
    const std::string flags = std::string(" --size 128x128 --balance recommended --frames 4 ") + GetParam().flags;
    const std::string args = (std::string(GetParam().name) == "view_across" ? "" : along) + flags;
    const Outcome o = run(args + " -q --image '' --report " + (dir_ / "r.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json r = json::parse(slurp(dir_ / "r.json"));
    ASSERT_EQ(r["frames"].size(), 4u);
    EXPECT_EQ(r["comparison"]["balanced_policy"], "measured");
    EXPECT_LE(r["comparison"]["ratio"].get<double>(), 1 / 0.98) << r["comparison"].dump();
    for (const json& f : r["frames"])  // no frame of the sequence, the first included
        EXPECT_LE(f["render_time_ns"].get<double>(), r["frames"][0]["render_time_ns"].get<double>() / 0.98) << f.dump();
}

INSTANTIATE_TEST_SUITE_P(FailureCases, NeverHurts,
                         testing::Values(Hurt{"links_3us", "--link-latency 3us"},
                                         Hurt{"links_300MBps", "--link-bandwidth 300MB/s"},
                                         Hurt{"spheres_everywhere", "--concentration 1"},
                                         Hurt{"view_across", ""}),
                         [](const testing::TestParamInfo<Hurt>& i) { return std::string(i.param.name); });

// --faces ideal-layer (models/balance/ideal_layer_faces.h). Spheres everywhere,
// viewed across the axis (rtsim's camera): `slide`'s columns move their
// faces apart, and rays crossing into a neighbouring column whose face is
// elsewhere are passed on untraced. With the layer's shared planes the faces
// stay in line, up to the columns' lag in reaching them; the image is the
// unbalanced run's, byte for byte.
TEST_F(Rtsim, IdealLayerFacesStayInLineAndKeepTheImage) {
    const std::string procedural = " --spheres 1000 --radius 0.02 --seed 5 --concentration 1 --size 96x96 -q";
    auto between = [&](const std::string& flags, const std::string& image) {
        const Outcome o = run(procedural + flags + " --image " + (dir_ / image).string() + " --report " +
                              (dir_ / "r.json").string());
        EXPECT_EQ(o.code, 0) << o.err;
        EXPECT_EQ(o.err, "");  // the baseline and the balancing comparison ran (their policies share no faces)
        const json r = json::parse(slurp(dir_ / "r.json"));
        EXPECT_TRUE(r.contains("baseline"));
        return std::make_pair(r["totals"]["rays_passed_between_columns"].get<uint64_t>(),
                              r["balance"].value("slides", 0));
    };
    const auto none = between(" --balance none", "none.png");
    const auto columns = between(" --balance slide", "columns.png");
    const auto layers = between(" --balance slide --faces ideal-layer", "layers.png");
    EXPECT_EQ(none.second, 0);
    EXPECT_GT(layers.second, 50);
    EXPECT_GT(columns.first, 400u);
    EXPECT_LT(layers.first * 5, columns.first) << layers.first << " against " << columns.first;
    EXPECT_EQ(slurp(dir_ / "layers.png"), slurp(dir_ / "none.png"));
    EXPECT_EQ(slurp(dir_ / "columns.png"), slurp(dir_ / "none.png"));
    // Only with slide's rule, in one frame from faces in line: one line each.
    for (const char* bad : {" --balance work --faces ideal-layer", " --balance slide --faces ideal-layer --frames 2",
                            " --balance slide --faces aligned"})
        expectBad(procedural + bad, "--faces");
}

// Issue 11's age target at the ends of the link sweep, with the control
// lane: the 95th percentile age of the loads slide's decisions
// used is at most 2 intervals plus a report's own crossing of one link
// (latency + 52 bytes at the link's bandwidth), and the reports cost no more
// than 2 % of the frame. On the rays' FIFO the 100 us case reached 10.3
// intervals, and without pacing the 10 MB/s one made the frame 13 % longer.
struct Speed {
    const char* name;
    const char* flags;
    double latencyUs, bytesPerUs;
};
class LoadAges : public Rtsim, public testing::WithParamInterface<Speed> {};

TEST_P(LoadAges, StayWithinTwoIntervalsAndAReportsCrossing) {
    const Speed& s = GetParam();
    const Outcome o = run(std::string(" --eye=-1.3,0.5,0.5 --look-at=0.5,0.5,0.5 --fov 50 --size 64x64 --balance slide"
                                      " --link-control-depth 2 ") +
                          s.flags + " -q --image '' --report " + (dir_ / "r.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json r = json::parse(slurp(dir_ / "r.json"));
    const double interval = 20, reportBytes = 8 + 44;  // us: rtsim's default interval
    const double target = 2 + (s.latencyUs + reportBytes / s.bytesPerUs) / interval;
    ASSERT_GT(r["balance"]["decisions"].get<int>(), 100);
    EXPECT_LE(r["balance"]["load_age_intervals"]["p95"].get<double>(), target) << r["balance"].dump();
    EXPECT_LE(r["comparison"]["ratio"].get<double>(), 1 / 0.98) << r["comparison"].dump();
}

INSTANTIATE_TEST_SUITE_P(LinkSweepEnds, LoadAges,
                         testing::Values(Speed{"latency_10ns", "--link-latency 10ns", 0.01, 1000},
                                         Speed{"latency_100us", "--link-latency 100us", 100, 1000},
                                         Speed{"bandwidth_10MBps", "--link-bandwidth 10MB/s", 0.1, 10},
                                         Speed{"bandwidth_100GBps", "--link-bandwidth 100GB/s", 0.1, 100000}),
                         [](const testing::TestParamInfo<Speed>& i) { return std::string(i.param.name); });

TEST_F(Rtsim, WithoutTheGuardTheSlowLinksCaseLoses) {
    const Outcome o = run(" --eye=-1.3,0.5,0.5 --look-at=0.5,0.5,0.5 --fov 50 --size 128x128 --balance slide "
                          "--link-latency 3us --no-guard -q --image '' --report " + (dir_ / "r.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json r = json::parse(slurp(dir_ / "r.json"));
    EXPECT_GT(r["comparison"]["ratio"].get<double>(), 1.1) << r["comparison"].dump();
}

// The 1987 machine at its bandwidth knee (360 KB/s links, N = 2): without
// the busy-link guard (--guard-wire 0) slide's slides pass the
// cost test, but each moves work across a link the rays already fill, and
// the frame becomes link-bound: 1.19 times the unbalanced frame. With the
// guard at its default (1: a full link) a slide that would fill the link
// (its last interval's share plus the rays the slab's work sends across) is
// stopped, and the frame is shorter than the unbalanced one (0.88).
TEST_F(Rtsim, TheBusyLinkGuardKeepsBalancingFromLosingAtTheBandwidthKnee) {
    const std::string args = " --config " RT_CONFIG_DIR "/transputer-1987.conf --spheres 1000 --concentration 0.25 "
                             "--size 128x128 --mesh 2 --link-latency 1.5us --link-bandwidth 360KB/s --balance slide "
                             "-q --image '' --report " + (dir_ / "r.json").string();
    const Outcome without = run(args + " --guard-wire 0");
    ASSERT_EQ(without.code, 0) << without.err;
    const json w = json::parse(slurp(dir_ / "r.json"));
    EXPECT_GT(w["comparison"]["ratio"].get<double>(), 1.1) << w["comparison"].dump();
    EXPECT_EQ(w["balance"]["guard_busy_link"], 0);
    EXPECT_EQ(w["config"]["balance"]["guard_wire_share"], 0.0);
    const Outcome with = run(args);
    ASSERT_EQ(with.code, 0) << with.err;
    const json g = json::parse(slurp(dir_ / "r.json"));
    EXPECT_LE(g["comparison"]["ratio"].get<double>(), 1 / 0.98) << g["comparison"].dump();
    EXPECT_GT(g["balance"]["guard_busy_link"].get<int>(), 0);
    EXPECT_EQ(g["config"]["balance"]["guard_wire_share"], 1.0);
}

// The busy-link guard counts a link's slots where they, not its wire, are
// the narrower limit (Link::occupied). The 1987 machine with 200 us links:
// a ray message takes 110 us on the wire (132 bytes at 1.2 MB/s), but with
// 2 slots each holds one for 110 + 2 x 200 us, so the link carries one
// every 255 us at best. No wire is busy a third of the frame, yet the guard
// stops slides across links whose slots are full (30 here), and the frame is
// 0.90 of the unbalanced one. With 64 slots the wire is the narrower limit
// again ((110 + 400) / 64 < 110 us), busier (0.42 of the frame), and the
// guard stops a tenth as many or fewer (1 here).
TEST_F(Rtsim, TheBusyLinkGuardCountsALinksSlotsWhereTheyAreTheNarrowerLimit) {
    const std::string args = " --config " RT_CONFIG_DIR "/transputer-1987.conf --spheres 1000 --concentration 0.25 "
                             "--size 128x128 --mesh 2 --link-latency 200us --balance slide -q --image '' --report " +
                             (dir_ / "r.json").string();
    auto busiestWire = [](const json& r) {
        double u = 0;
        for (const json& l : r["links"])
            if (l["to"] != "fb") u = std::max(u, l["utilisation"].get<double>());
        return u;
    };
    ASSERT_EQ(run(args + " --link-depth 2").code, 0);
    const json two = json::parse(slurp(dir_ / "r.json"));
    EXPECT_LT(busiestWire(two), 0.34);
    EXPECT_GT(two["balance"]["guard_busy_link"].get<int>(), 0);
    EXPECT_LT(two["comparison"]["ratio"].get<double>(), 0.93) << two["comparison"].dump();
    ASSERT_EQ(run(args + " --link-depth 64").code, 0);
    const json many = json::parse(slurp(dir_ / "r.json"));
    EXPECT_GT(busiestWire(many), busiestWire(two));
    EXPECT_LE(10 * many["balance"]["guard_busy_link"].get<int>(), two["balance"]["guard_busy_link"].get<int>());
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
    expectBad("--map /nonexistent/m.png", "--map: /nonexistent/m.png");
    expectBad("--quantum soon", "--quantum");
    expectBad("--guard-wire -0.5", "--guard-wire");
    expectBad("--guard-wire busy", "--guard-wire");
    expectBad("--fb-units 0", "--fb-units");
    expectBad("--fb-units 257", "--fb-units");
    expectBad("--balance sometimes", "--balance");
    // `default` meant the recommended policy while the default of --balance was none: one name each now.
    expectBad("--balance default", "--balance: 'default' names no policy: the recommended policy is measured (or 'recommended')");
    expectBad("--eye nan,0,0", "--eye");
    expectBad("--light 1,nan,1", "--light");
    expectBad("--eye-step 0,inf,0 --frames 2", "--eye-step");
    std::ofstream(dir_ / "bad.ini") << "mesh = [not closed\n";
    expectBad("--config " + (dir_ / "bad.ini").string(), "");
    std::ofstream(dir_ / "bad2.ini") << "no-such-flag = 3\n";
    expectBad("--config " + (dir_ / "bad2.ini").string(), "no-such-flag");
    expectBad("--config /nonexistent.ini", "/nonexistent.ini");
    expectBad("--config /dev/urandom", "/dev/urandom");  // read whole, it never ended
    expectBad("--boundaries-from /dev/urandom", "--boundaries-from: not a regular file");
    expectBad("--size 65536x65536", "--size 65536x65536: needs at least");  // was bad_alloc, naming nothing
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

namespace {
// rtsim under `timeout`: a run the watchdog fails to stop fails the test in
// a minute instead of hanging the suite.
class RtsimTimed : public CommandTest {
protected:
    RtsimTimed() : CommandTest(std::string("timeout 60 ") + RTSIM_EXE) {}
};
}  // namespace

TEST_F(RtsimTimed, WatchdogTurnsALostCreditIntoExit3UnderEveryPolicy) {
    // Unit 0 loses the first credit it takes: the frame can never complete.
    // With balancing the nodes keep waking for their intervals and the run
    // never ended; without, it ended with "frame never completed" (exit 1).
    for (const char* p : {"none", "slide", "work", "quantile", "resplit", "measured", "median"}) {
        SCOPED_TRACE(p);
        const fs::path report = dir_ / (std::string(p) + ".json"), vcd = dir_ / (std::string(p) + ".vcd"),
                       image = dir_ / (std::string(p) + ".png");
        const Outcome o = run(std::string(kSmall) + " --mesh 3 --balance " + p +
                              " --fault-drop-credit --no-baseline -q --report " + report.string() + " --vcd " +
                              vcd.string() + " --image " + image.string());
        EXPECT_EQ(o.code, 3) << o.err;
        EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
        EXPECT_EQ(o.err.rfind("rtsim: error: watchdog: no ray, contribution or credit moved for ", 0), 0u) << o.err;
        EXPECT_NE(o.err.find("unit 0 has 0.9"), std::string::npos) << o.err;
        ASSERT_TRUE(fs::exists(report));
        const json r = json::parse(slurp(report));
        ASSERT_TRUE(r.contains("incomplete"));
        EXPECT_NE(r["incomplete"].get<std::string>().find("no ray, contribution or credit moved"), std::string::npos);
        EXPECT_NE(slurp(vcd).find("$comment incomplete: "), std::string::npos);
        EXPECT_FALSE(fs::exists(image));  // no image from a frame that did not end
    }
    // The same run without the lost credit ends and says nothing of the kind.
    const Outcome ok = run(std::string(kSmall) + " --mesh 3 --balance slide --no-baseline -q --image '' --report " +
                           (dir_ / "ok.json").string());
    ASSERT_EQ(ok.code, 0) << ok.err;
    EXPECT_FALSE(json::parse(slurp(dir_ / "ok.json")).contains("incomplete"));
}

// An earlier frame of a --frames sequence runs in a child process; the
// watchdog stopping it stops the sequence with exit 3 too (it was exit 1,
// "frame 1 of 3 failed"), with that frame's report so far.
TEST_F(RtsimTimed, WatchdogInAnEarlierFrameStopsTheSequenceWithExit3) {
    const fs::path report = dir_ / "frames.json";
    const Outcome o = run(std::string(kSmall) + " --mesh 3 --frames 3 --balance slide --fault-drop-credit"
                                                " --no-baseline -q --image '' --report " + report.string());
    EXPECT_EQ(o.code, 3) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
    EXPECT_EQ(o.err.rfind("rtsim: error: watchdog: no ray, contribution or credit moved", 0), 0u) << o.err;
    ASSERT_TRUE(fs::exists(report));
    const json r = json::parse(slurp(report));
    EXPECT_EQ(r.value("incomplete", std::string()).rfind("frame 1 of 3: no ray, contribution or credit moved", 0), 0u);
    ASSERT_EQ(r["frames"].size(), 1u);
    EXPECT_TRUE(r["frames"][0].value("incomplete", false));
}

// The VCD is written as the run goes, into VCD.incomplete-XXXXXX beside
// it (renamed at the end): a run killed outright leaves that, which
// vcd2fst accepts (up to the last flush), and no VCD under the name given;
// Ctrl-C stops the run like the watchdog (exit 128 + 2, the report and the
// VCD so far, marked).
TEST_F(RtsimTimed, AKilledOrInterruptedRunLeavesAValidVcd) {
    const std::string job = " --scene " + scene("balls-4") + " --mesh 4 --size 256x256 --no-baseline -q --image " +
                            (dir_ / "never.png").string();
    for (const char* sig : {"KILL", "INT"}) {
        SCOPED_TRACE(sig);
        const fs::path vcd = dir_ / (std::string(sig) + ".vcd"), rep = dir_ / (std::string(sig) + ".json");
        // Signalled once the VCD has value changes on disk (however fast
        // this build runs), within a minute.
        const std::string cmd = "bash -c '" + std::string(RTSIM_EXE) + job + " --vcd " + vcd.string() + " --report " +
                                rep.string() + " 2>" + (dir_ / "err").string() + " & p=$!; for i in $(seq 1200); do "
                                "[ $(cat " + vcd.string() + ".incomplete-* 2>/dev/null | wc -c) -gt 200000 ] && break; sleep 0.05; done; "
                                "kill -" + sig + " $p; wait $p'";
        const int status = std::system(cmd.c_str());
        const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        std::vector<fs::path> left;  // the temporaries left behind
        for (const auto& e : fs::directory_iterator(dir_))
            if (e.path().filename().string().rfind(std::string(sig) + ".", 0) == 0 &&
                e.path().string().find(".incomplete-") != std::string::npos)
                left.push_back(e.path());
        if (std::string(sig) == "KILL") {
            EXPECT_FALSE(fs::exists(vcd));  // nothing under the name given: the run did not end
            ASSERT_EQ(left.size(), 1u);     // the VCD so far, under a name that says so
            fs::rename(left[0], vcd);
        } else {
            EXPECT_TRUE(left.empty());  // renamed: an interrupted run ends in order
        }
        ASSERT_TRUE(fs::exists(vcd));
        const std::string text = slurp(vcd);
        EXPECT_NE(text.find("$enddefinitions $end"), std::string::npos);
        EXPECT_NE(text.find("\n#"), std::string::npos);  // value changes, not just the header
        const std::string conv = "vcd2fst " + vcd.string() + " " + (dir_ / "x.fst").string() + " >" + (dir_ / "v2f").string() + " 2>&1";
        EXPECT_EQ(std::system(conv.c_str()), 0) << slurp(dir_ / "v2f");
        if (std::string(sig) == "INT") {
            EXPECT_EQ(code, 130) << slurp(dir_ / "err");
            EXPECT_NE(text.find("$comment incomplete: interrupted by signal 2"), std::string::npos);
            ASSERT_TRUE(fs::exists(rep));
            EXPECT_EQ(json::parse(slurp(rep)).value("incomplete", "").rfind("interrupted by signal 2", 0), 0u);
        } else {
            EXPECT_EQ(code, 128 + 9);  // (the shell's code for a process killed by SIGKILL)
            EXPECT_FALSE(fs::exists(rep));
        }
        EXPECT_FALSE(fs::exists(dir_ / "never.png"));
    }
}

TEST_F(RtsimTimed, WatchdogSpanAndWallClockLimit) {
    // The span as given: stopped at the first check at least a span after
    // the last progress (checks every span up to 1 ms).
    const Outcome s = run(std::string(kSmall) + " --mesh 2 --fault-drop-credit --watchdog 50us --no-baseline -q --image ''");
    EXPECT_EQ(s.code, 3) << s.err;
    const size_t at = s.err.find("moved for ");
    ASSERT_NE(at, std::string::npos) << s.err;
    std::istringstream moved(s.err.substr(at + 10));
    double quiet = 0;
    std::string unit;
    moved >> quiet >> unit;
    EXPECT_EQ(unit, "us") << s.err;
    EXPECT_GE(quiet, 50.0) << s.err;  // a span, and less than two
    EXPECT_LT(quiet, 100.0) << s.err;
    // A span no run would reach (1,000 s, balancing waking the nodes every
    // 20 us of it): the wall-clock limit stops it.
    const Outcome w = run(std::string(kSmall) + " --mesh 2 --balance slide --fault-drop-credit --watchdog 1000s"
                                                " --watchdog-wall 0.5 --no-baseline -q --image ''");
    EXPECT_EQ(w.code, 3) << w.err;
    EXPECT_NE(w.err.find("the wall-clock limit of 0.5 s was reached"), std::string::npos) << w.err;
}

// A busy run stopped midway (here by the wall clock) ends at the kernel's
// time, which nodes reading their input only when they must (no dynamic
// policy) may have worked past: the run still ends as incomplete (exit 3,
// not an error), and every node's busy and wait make up the time reached.
TEST_F(RtsimTimed, ABusyRunStoppedMidwayEndsIncompleteWithItsTimeAccounted) {
    const fs::path report = dir_ / "stopped.json";
    // The limit counts from rtsim's start: it must pass start-up (0.02 s;
    // 0.1 s under AddressSanitizer, more on a loaded machine, and a limit
    // in start-up writes nothing) and stop the frame well before its end
    // (about 10 s at 1024x1024). A limit that lands in start-up is doubled.
    Outcome o;
    std::string limit;
    for (const char* l : {"0.3", "0.6", "1.2", "2.4"}) {
        limit = l;
        o = run(" --scene " + scene("balls-4") + " --mesh 4 --size 1024x1024 --watchdog-wall " + limit +
                " --no-baseline -q --image '' --report " + report.string());
        if (o.err.find("during start-up") == std::string::npos) break;
    }
    ASSERT_EQ(o.code, 3) << o.err;
    EXPECT_NE(o.err.find("the wall-clock limit of " + limit + " s was reached at "), std::string::npos) << o.err;
    const json r = json::parse(slurp(report));
    const auto end = std::llround(r["render_time_ns"].get<double>() * 1000);
    double busy = 0;
    for (const json& n : r["nodes"]) {
        EXPECT_EQ(std::llround((n["busy_ns"].get<double>() + n["wait_ns"].get<double>()) * 1000), end) << n["node"];
        EXPECT_LE(std::llround(n["last_active_ns"].get<double>() * 1000), end) << n["node"];
        busy += n["busy_ns"].get<double>();
    }
    EXPECT_GT(busy, 0.0);
}

// Finite output buffers (--link-out-depth): with one slot per link and one
// message of output buffer, nodes that send rays both ways fill each
// other's links and block each other (doc/machine.md, "Finite output
// buffers"): a deadlock under every policy, which the watchdog reports with
// the nodes blocked and where.
TEST_F(RtsimTimed, FullOutputBuffersDeadlockAndTheWatchdogNamesTheBlockedNodes) {
    for (const char* p : {"none", "slide", "work", "quantile", "resplit", "measured", "median"}) {
        SCOPED_TRACE(p);
        const fs::path report = dir_ / (std::string(p) + ".json");
        const Outcome o = run(std::string(kSmall) + " --mesh 3 --link-depth 1 --link-out-depth 1 --balance " + p +
                              " --no-baseline -q --image '' --report " + report.string());
        EXPECT_EQ(o.code, 3) << o.err;
        EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
        EXPECT_NE(o.err.find("blocked on its full output to "), std::string::npos) << o.err;
        ASSERT_TRUE(fs::exists(report));
        const json r = json::parse(slurp(report));
        EXPECT_TRUE(r.contains("incomplete"));
        EXPECT_GT(r["totals"]["blocked_ns"].get<double>(), 0.0);
        for (const json& n : r["nodes"]) {
            EXPECT_LE(n["blocked_ns"].get<double>(), n["wait_ns"].get<double>());  // blocked time is wait
            EXPECT_NEAR(n["busy_ns"].get<double>() + n["wait_ns"].get<double>(), r["render_time_ns"].get<double>(), 1e-3);
        }
    }
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

TEST_F(Rtsim, BoundariesInTheWaveformAndTheSummary) {
    const std::string vcd = (dir_ / "b.vcd").string();
    const Outcome o = run(std::string(kSmall) + " --mesh 2 --balance slide --gain 1 --balance-interval 2us --no-baseline"
                                                " --image '' --vcd " + vcd);
    ASSERT_EQ(o.code, 0) << o.err;
    const std::string text = slurp(vcd);
    EXPECT_NE(text.find("$scope module boundaries $end"), std::string::npos);
    EXPECT_NE(text.find("$var real 64"), std::string::npos);
    EXPECT_NE(text.find(" slides $end"), std::string::npos);
    EXPECT_NE(slurp(dir_ / "b.gtkw").find("machine.boundaries.col_0_0_b1.position"), std::string::npos);
    const std::string cmd = "vcd2fst " + vcd + " " + (dir_ / "b.fst").string() + " >/dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    EXPECT_NE(o.out.find("balancing        slide along x"), std::string::npos) << o.out;
    const json r = report(std::string(kSmall) + " --mesh 2 --balance slide --gain 1 --balance-interval 2us");
    EXPECT_GT(r["balance"]["slides"].get<size_t>(), 0u);
    EXPECT_EQ(r["boundaries"].size(), 4u);  // a 2x2x2 mesh: 4 columns along x, one boundary each
    EXPECT_TRUE(r["nodes"][0].contains("intervals"));
}

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

// ---- Frames: the boundaries carried from one frame to the next ----

namespace {
// Each column's inner boundaries where a report's run ended them, keyed by
// (column, index); and where it started them.
std::map<std::pair<std::string, int>, double> boundaryEnds(const json& r, bool last) {
    std::map<std::pair<std::string, int>, double> m;
    for (const json& h : r["boundaries"])
        m[{h["column"].dump(), h["index"].get<int>()}] = (last ? h["history"].back() : h["history"].front())[1].get<double>();
    return m;
}
const char* kSliding = " --spheres 300 --radius 0.03 --size 48x48 --mesh 3 --balance slide --balance-interval 5us"
                       " --eye=-1.3,0.5,0.5 --look-at=0.5,0.5,0.5 --fov 50";
}  // namespace

TEST_F(Rtsim, BoundariesFromAReportStartWhereItsRunEnded) {
    const json a = report(kSliding, "a.json");
    ASSERT_GT(a["balance"]["slides"].get<int>(), 0);
    const json b = report(std::string(kSliding) + " --boundaries-from " + (dir_ / "a.json").string(), "b.json");
    const auto ended = boundaryEnds(a, true), started = boundaryEnds(b, false);
    ASSERT_EQ(ended.size(), 3u * 3 * 2);
    EXPECT_EQ(ended, started);
    // Not where a run starts on its own: the uniform split.
    EXPECT_NE(boundaryEnds(a, false), started);
}

TEST_F(Rtsim, FramesCarryTheBoundariesAndEachFrameIsARunFromThePreviousOne) {
    // Three frames in one command against the same three frames run by hand,
    // each from the report of the one before: the same render times, and
    // the last frame's image is the image (the same as without balancing).
    const json f = report(std::string(kSliding) + " --frames 3", "f.json");
    ASSERT_EQ(f["frames"].size(), 3u);
    std::vector<double> byHand;
    std::string from;
    for (int k = 0; k < 3; ++k) {
        const std::string name = "h" + std::to_string(k) + ".json";
        const json h = report(std::string(kSliding) + from, name);
        byHand.push_back(h["render_time_ns"].get<double>());
        from = " --boundaries-from " + (dir_ / name).string();
    }
    for (int k = 0; k < 3; ++k) EXPECT_EQ(f["frames"][k]["render_time_ns"].get<double>(), byHand[size_t(k)]) << k;
    EXPECT_EQ(f["render_time_ns"].get<double>(), byHand[2]);
    EXPECT_NE(byHand[0], byHand[1]);  // the second frame starts elsewhere
    ASSERT_EQ(run(std::string(kSliding) + " --frames 3 -q --no-baseline --image " + (dir_ / "f.png").string()).code, 0);
    ASSERT_EQ(run(std::string(kSliding) + " --balance none -q --no-baseline --image " + (dir_ / "n.png").string()).code, 0);
    EXPECT_EQ(slurp(dir_ / "f.png"), slurp(dir_ / "n.png"));
}

TEST_F(Rtsim, ACameraPathMovesTheEyeEachFrame) {
    // Frame 3 of a path is the view moved two steps: the same image as one
    // frame rendered from there.
    const std::string scene = " --spheres 300 --radius 0.03 --size 48x48 --mesh 2 --look-at=0.5,0.5,0.5 -q --no-baseline";
    ASSERT_EQ(run(scene + " --eye=-1.3,0.5,0.5 --eye-step 0,0.2,0.1 --frames 3 --balance slide --image " +
                  (dir_ / "p.png").string()).code, 0);
    ASSERT_EQ(run(scene + " --eye=-1.3,0.9,0.7 --balance none --image " + (dir_ / "q.png").string()).code, 0);
    ASSERT_EQ(run(scene + " --eye=-1.3,0.5,0.5 --balance none --image " + (dir_ / "r.png").string()).code, 0);
    EXPECT_EQ(slurp(dir_ / "p.png"), slurp(dir_ / "q.png"));
    EXPECT_NE(slurp(dir_ / "p.png"), slurp(dir_ / "r.png"));
}

TEST_F(Rtsim, BoundariesFromAnotherMeshIsBadInput) {
    report(std::string(kSliding), "a.json");
    const Outcome o = run(std::string(kSliding) + " --mesh 2 -q --image '' --boundaries-from " + (dir_ / "a.json").string());
    EXPECT_EQ(o.code, 2);
    EXPECT_NE(o.err.find("--boundaries-from"), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("another mesh"), std::string::npos) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
    std::ofstream(dir_ / "bad.json") << "{ not json";
    EXPECT_EQ(run(std::string(kSliding) + " -q --image '' --boundaries-from " + (dir_ / "bad.json").string()).code, 2);
}

TEST_F(Rtsim, ResplitMovesTheBoundariesAtTheStartOfEachFrameAndKeepsTheFastest) {
    // Frame 1 balances as slide; every later frame starts by moving each
    // face once, at time 0, to the quantiles of the frame before's busy
    // time, and holds it. Over eight frames it settles on the fastest split
    // it has seen, well below the unbalanced frame.
    const std::string k = std::string(kSliding) + " --balance resplit";
    const json none = report(std::string(kSliding) + " --balance none", "n.json");
    const json f = report(k + " --frames 8", "f.json");
    ASSERT_EQ(f["frames"].size(), 8u);
    EXPECT_GT(f["frames"][0]["slides"].get<int>(), 18);
    double fastest = 1e300;
    for (size_t i = 1; i < 8; ++i) {
        // Each face of the 3 x 3 columns at most twice: once, or, when its
        // target lies past the next box, what that box has and then the rest.
        EXPECT_LE(f["frames"][i]["slides"].get<int>(), 2 * 3 * 3 * 2) << i;
        if (i < 7) fastest = std::min(fastest, f["frames"][i]["render_time_ns"].get<double>());
    }
    // The last frames hold the fastest frame's planes. A frame that holds
    // them is not the one that moved to them (no slides at its start), so
    // the order its work happens in, and its time, may differ a little.
    EXPECT_EQ(f["frames"][6]["then"]["next"], "held");
    EXPECT_LE(f["render_time_ns"].get<double>(), 1.005 * fastest);
    EXPECT_LT(f["render_time_ns"].get<double>(), 0.8 * none["render_time_ns"].get<double>());
    // The moves of a re-split frame happen at its start.
    const json g = report(k + " --frames 3", "g.json");
    ASSERT_GT(g["balance"]["slides"].get<int>(), 0);
    for (const json& h : g["boundaries"])
        for (const json& p : h["history"]) EXPECT_LT(p[0].get<double>(), 1000.0) << h.dump();
    ASSERT_EQ(run(k + " --frames 3 -q --no-baseline --image " + (dir_ / "g.png").string()).code, 0);
    ASSERT_EQ(run(std::string(kSliding) + " --balance none -q --no-baseline --image " + (dir_ / "n.png").string()).code, 0);
    EXPECT_EQ(slurp(dir_ / "g.png"), slurp(dir_ / "n.png"));
}

TEST_F(Rtsim, FramesWithOneNodeAlongTheBalancingAxis) {
    // No boundaries to carry from frame to frame: found by scripts/stress.py
    // (the report had no "boundaries" and the frame loop stopped, exit 1).
    for (const char* p : {"slide", "resplit", "measured", "quantile"}) {
        SCOPED_TRACE(p);
        const json r = report(std::string(kSmall) + " --mesh-dims 2x1x2 --axis y --frames 2 --balance " + p);
        EXPECT_EQ(r["frames"].size(), 2u);
        EXPECT_TRUE(r["boundaries"].empty());
    }
}

ResplitAgainstNone Rtsim::resplitAgainstNone(const std::string& bandwidth, const std::string& scene) {
    const std::string k = scene + " --size 48x48 --balance-interval 5us"
                          " --link-bandwidth " + bandwidth;
    const json f = report(k + " --balance resplit --frames 6", "f.json");
    ResplitAgainstNone r{{}, {}, f["render_time_ns"].get<double>(),
                         report(k + " --balance none", "n.json")["render_time_ns"].get<double>()};
    for (const json& frame : f["frames"]) {
        r.ns.push_back(frame["render_time_ns"].get<double>());
        r.slides.push_back(frame["slides"].get<int>());
    }
    EXPECT_EQ(r.ns.size(), 6u);
    r.ns.resize(6, -1);  // (a short sequence fails the checks, not the test binary)
    r.slides.resize(6, -1);
    return r;
}

TEST_F(Rtsim, ResplitGoesBackToTheFirstFrameWhereReSplittingDoesNotPay) {
    // 500 spheres over half the world, 4x4x4, 150 MB/s: the forecast holds
    // frame 1's planes (its slides made none), so neither frame 2 nor 3
    // beats the first, which its load reports' small gain did; frame 4
    // holds the split frame 1 started from (to the picosecond the
    // unbalanced run), and since it does not beat frame 1 either, every
    // later frame is the first one again.
    const ResplitAgainstNone f = resplitAgainstNone("150MB/s", " --spheres 500 --radius 0.02 --concentration 0.5 --mesh 4");
    const double first = f.ns[0];
    EXPECT_LT(first, f.none);
    EXPECT_GT(f.ns[1], first);
    EXPECT_GT(f.ns[2], first);
    EXPECT_EQ(f.ns[3], f.none);
    EXPECT_EQ(f.slides[3], 0);
    EXPECT_EQ(f.ns[4], first);
    EXPECT_EQ(f.ns[5], first);
    EXPECT_EQ(f.last, first);
}

TEST_F(Rtsim, ResplitHoldsThePlanesWhereTheForecastSeesNoGain) {
    // Spheres spread evenly, 30 MB/s: the frame is the links' (slide's first
    // frame makes no slide, and its load reports make it slower than the
    // unbalanced one):
    // the forecast from frame 1 finds no planes that would be faster, so
    // frames 2 to 6 hold frame 1's planes, the starting split, with no
    // slides and no load reports: the unbalanced run's time to the picosecond.
    const ResplitAgainstNone f = resplitAgainstNone("30MB/s");
    EXPECT_GT(f.ns[0], f.none);
    for (int i = 1; i < 6; ++i) {
        EXPECT_EQ(f.ns[size_t(i)], f.none) << "frame " << i + 1;
        EXPECT_EQ(f.slides[size_t(i)], 0) << "frame " << i + 1;
    }
    EXPECT_EQ(f.last, f.none);
    const json r = report(" --spheres 300 --radius 0.03 --concentration 1 --size 48x48 --mesh 3 --balance-interval 5us --link-bandwidth 30MB/s"
                          " --balance resplit --frames 2", "h.json");
    EXPECT_EQ(r["frames"][0]["then"]["next"], "held");
    EXPECT_LT(r["frames"][0]["then"]["forecast_ns"].get<double>(), 1.01 * r["frames"][1]["render_time_ns"].get<double>());
}

TEST_F(Rtsim, WhereTheLinksAreTheFrameColumnsOwnPlanesMustBeatAlignedOnesClearly) {
    // tetra-3, N = 6, 100 MB/s: the links are the frame. The forecast puts
    // the columns' own planes 1.7 % ahead of one set for all, but they pass
    // rays between columns, which it counts short there: they measured 1.14
    // of the first frame, the aligned planes 0.95. So the aligned planes
    // are chosen, and the second frame does not lose.
    const json r = report(" --scene " + std::string(RT_SCENE_DIR) + "/tetra-3.nff --size 256x256 --mesh 6"
                          " --link-bandwidth 100MB/s --balance recommended --frames 2", "t.json");
    EXPECT_EQ(r["frames"][0]["then"]["next"], "aligned");
    EXPECT_LT(r["frames"][1]["render_time_ns"].get<double>(), r["frames"][0]["render_time_ns"].get<double>());
}

TEST_F(Rtsim, AReSplitFrameGeneratesEachPrimaryRayInTheBoxItMovesTo) {
    // Targets for the frame's start, the same planes in every column: each
    // node generates the primary rays of the box it is to have, once its
    // faces are there, so no ray is passed on (before, the nodes generated
    // them in the boxes they started with and passed 265 on); the image is
    // the unbalanced run's.
    const std::string k = " --spheres 300 --radius 0.03 --size 48x48 --mesh 3 --no-baseline -q";
    ASSERT_EQ(run(k + " --balance none --report " + (dir_ / "n.json").string() + " --image " + (dir_ / "n.png").string()).code, 0);
    std::ofstream(dir_ / "t.json") << nlohmann::json(std::vector<std::vector<double>>(9, {0.3, 0.55})).dump();
    const Outcome o = run(k + " --balance measured --boundaries-from " + (dir_ / "n.json").string() + " --targets-from " +
                          (dir_ / "t.json").string() + " --report " + (dir_ / "m.json").string() + " --image " +
                          (dir_ / "m.png").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json m = json::parse(slurp(dir_ / "m.json"));
    EXPECT_EQ(m["balance"]["slides"].get<int>(), 18);
    EXPECT_EQ(m["totals"]["rays_passed"].get<int>(), 0);
    for (const json& h : m["boundaries"]) EXPECT_DOUBLE_EQ(h["history"].back()[1].get<double>(), h["index"] == 1 ? 0.3 : 0.55);
    EXPECT_EQ(slurp(dir_ / "m.png"), slurp(dir_ / "n.png"));
    // A target box thinner than the minimum could never be reached (nor
    // its primary rays generated): refused, in one line.
    std::ofstream(dir_ / "thin.json") << nlohmann::json(std::vector<std::vector<double>>(9, {0.3, 0.3001})).dump();
    const Outcome thin = run(k + " --balance measured --boundaries-from " + (dir_ / "n.json").string() +
                             " --targets-from " + (dir_ / "thin.json").string() + " --image ''");
    EXPECT_EQ(thin.code, 1) << thin.err;  // (the run refuses it, as a start box too thin)
    EXPECT_NE(thin.err.find("thinner than the minimum thickness"), std::string::npos) << thin.err;
    EXPECT_EQ(std::count(thin.err.begin(), thin.err.end(), '\n'), 1) << thin.err;
}

// A report reruns its run (tb/rerun.h): the flags it records, from another
// folder, give the same report (wall-clock figures and the rerun's own
// record aside) and the same image; flags given after --rerun change what
// they name; an edited scene file, or a report without flags, is refused.
TEST_F(Rtsim, AReportRerunsToTheSameRun) {
    const fs::path scene = dir_ / "scene.nff", elsewhere = dir_ / "elsewhere";
    fs::copy_file(fs::path(RT_SCENE_DIR) / "balls-1.nff", scene);
    std::ofstream(dir_ / "more.conf") << "link-depth = 3\nnode-speed = [\"1,0,0=0.5\"]\n";
    fs::create_directories(elsewhere);
    struct Case {
        const char* name;
        std::string args;
    };
    const std::vector<Case> cases{
        {"file", "--scene scene.nff --size 24x24 --mesh-dims 3x2x1 --balance slide --no-guard --gain 0.4"
                 " --link-set 0,0,0,+x:latency=1us,bandwidth=200MB/s --node-cost 1,1,0:sphere=30ns --frames 2"},
        {"procedural", std::string(kSmall) + " --mesh 2 --concentration 0.5 --seed 9 --light 1,2,3 --light 0,-2,1"
                       " --eye 0.5,-2,0.6 --cost-recv 70ns --quantum 0 --ray-batch 4 --fb-units 3 --config more.conf"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string name = c.name;
        const Outcome o = run(c.args + " -q --image " + name + ".png --report " + name + ".json", dir_);
        ASSERT_EQ(o.code, 0) << o.err;
        const Outcome again = run("--rerun ../" + name + ".json -q --image again.png --report again.json", elsewhere);
        ASSERT_EQ(again.code, 0) << again.err;
        EXPECT_EQ(slurp(dir_ / (name + ".png")), slurp(elsewhere / "again.png"));
        json a = json::parse(slurp(dir_ / (name + ".json"))), b = json::parse(slurp(elsewhere / "again.json"));
        EXPECT_EQ(b["rerun"]["of"], a["rerun"]);
        EXPECT_EQ(b["rerun"]["flags"], a["rerun"]["flags"]);
        a.erase("rerun");
        b.erase("rerun");
        dropWall(a);
        dropWall(b);
        EXPECT_EQ(a["render_time_ns"], b["render_time_ns"]);
        EXPECT_EQ(a, b);
        // A flag after --rerun changes what it names, and nothing is refused.
        const Outcome what = run("--rerun ../" + name + ".json --link-latency 777ns -q --image '' --report what.json", elsewhere);
        ASSERT_EQ(what.code, 0) << what.err;
        const json w = json::parse(slurp(elsewhere / "what.json"));
        EXPECT_EQ(w["config"]["link"]["latency_ns"], 777.0);
        EXPECT_EQ(w["config"]["mesh"], a["config"]["mesh"]);
        EXPECT_NE(w["render_time_ns"], a["render_time_ns"]);
    }
    // The scene file edited since: refused, naming it.
    std::ofstream(scene, std::ios::app) << "s 0 0 0 0.1\n";
    expectBad("--rerun " + (dir_ / "file.json").string(), "scene.nff has changed since");
    // Not a report with flags.
    std::ofstream(dir_ / "old.json") << "{\"config\": {}}";
    expectBad("--rerun " + (dir_ / "old.json").string(), "rerun.flags: missing");
    expectBad("--rerun " + (dir_ / "file.png").string(), "not JSON");
    expectBad("--rerun " + (dir_ / "file.json").string() + " --config " + (dir_ / "more.conf").string(), "cannot be combined");
}

// Messages go through SystemC's reporting with an ID per kind
// (tb/messages.h): with --verbose each line names its ID, and rtsim says
// what it does; without, the same one line and exit code as ever.
TEST_F(Rtsim, MessagesCarryTheirSystemCReportIds) {
    struct Case {
        std::string args;
        int code;
        const char* id;
    };
    std::ofstream(dir_ / "bad.nff") << "v\nfrom 0 0 nope\n";
    const std::vector<Case> cases{
        {"--scene " + (dir_ / "bad.nff").string(), 2, "rtsim/scene"},
        {"--scene " + (dir_ / "none.nff").string(), 2, "rtsim/config"},  // (a flag naming no file)
        {std::string(kSmall) + " --image /nonexistent/x.png", 2, "rtsim/output"},
        {"--mesh 0", 2, "rtsim/config"},
        {"--rerun " + (dir_ / "none.json").string(), 2, "rtsim/config"},
        {std::string(kSmall) + " --mesh 2 --fault-drop-credit --no-baseline -q --image ''", 3, "rtsim/watchdog"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args);
        const Outcome plain = run(c.args);
        EXPECT_EQ(plain.code, c.code) << plain.err;
        EXPECT_EQ(std::count(plain.err.begin(), plain.err.end(), '\n'), 1) << plain.err;
        EXPECT_EQ(plain.err.rfind("rtsim: error: ", 0), 0u) << plain.err;
        EXPECT_EQ(plain.err.find("[rtsim/"), std::string::npos) << plain.err;
        const Outcome v = run(c.args + " -v");
        EXPECT_EQ(v.code, c.code) << v.err;
        const std::string last = v.err.substr(v.err.rfind('\n', v.err.size() - 2) == std::string::npos ? 0 : v.err.rfind('\n', v.err.size() - 2) + 1);
        EXPECT_NE(last.find(std::string(" [") + c.id + "]\n"), std::string::npos) << v.err;
    }
    // What rtsim does, with -v only.
    const Outcome ok = run(std::string(kSmall) + " --mesh 2 --no-baseline -q --image '' -v");
    ASSERT_EQ(ok.code, 0) << ok.err;
    EXPECT_NE(ok.err.find("rtsim: quantum: each process's lookahead (the smallest 208 ns); watchdog after "), std::string::npos) << ok.err;  // a unit's: 200 ns and an 8-byte header at 1 GB/s
    EXPECT_NE(ok.err.find("[rtsim/info]"), std::string::npos) << ok.err;
    EXPECT_EQ(run(std::string(kSmall) + " --mesh 2 --no-baseline -q --image ''").err, "");
}

// The summary never calls boundaries converged over a frame that lost: the
// built-in scene at 64x64 on 33x1x1, where sample's frame takes 1.64 times
// the unbalanced one (its object-median start loses there), says which
// frame and how much; on 4x4x4 under measured, where no frame lost, it
// says converged and no more.
TEST_F(Rtsim, TheSummaryNamesAFrameThatLostBesideConvergedBoundaries) {
    const Outcome lost = run("--size 64x64 --mesh-dims 33x1x1 --balance sample --image ''");
    ASSERT_EQ(lost.code, 0) << lost.err;
    EXPECT_NE(lost.out.find("boundaries converged, but frame 1 took 1.6"), std::string::npos) << lost.out;
    const Outcome fine = run("--size 64x64 --balance measured --frames 3 --image ''");
    ASSERT_EQ(fine.code, 0) << fine.err;
    EXPECT_NE(fine.out.find("boundaries converged\n"), std::string::npos) << fine.out;
    EXPECT_EQ(fine.out.find(", but frame"), std::string::npos) << fine.out;
}

// The recommended policy on long columns, where moving the planes costs more
// than it saves: on the built-in scene at 64x64 its second frame took 3.5
// times the unbalanced one on 33x1x1, 4.0 on 64x1x1 and 1.37 on 64x2x1 (issue 61),
// the planes passed along chains of up to a dozen boxes. Counting that
// (move_forecast.h), no frame is slower than the unbalanced one by 2 %.
TEST_F(Rtsim, TheRecommendedPolicyNeverLosesOnALongColumn) {
    // (and 32 nodes along one axis, x or z)
    for (const char* dims : {"32x1x1", "33x1x1", "64x1x1", "64x2x1", "2x2x32 --axis z"}) {
        SCOPED_TRACE(dims);
        const Outcome o = run(std::string("--size 64x64 --balance measured --frames 3 -q --image '' --mesh-dims ") + dims +
                              " --report " + (dir_ / "r.json").string());
        ASSERT_EQ(o.code, 0) << o.err;
        const json r = json::parse(slurp(dir_ / "r.json"));
        ASSERT_EQ(r["frames"].size(), 3u);
        const double none = r["comparison"]["unbalanced_ns"].get<double>();
        for (const json& f : r["frames"]) EXPECT_LE(f["render_time_ns"].get<double>(), 1.02 * none) << f.dump();
    }
}
