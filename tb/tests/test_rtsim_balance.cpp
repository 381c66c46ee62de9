// rtsim end to end with balancing: the summary's comparison with the
// unbalanced frame, the cases where balancing must not lose, the guards,
// boundaries in the waveform, and frame sequences carrying the boundaries.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "rtsim_test.h"
#include "balance/between_frames.h"  // (kTrialReach)

using nlohmann::json;
using namespace rt::test;

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
    // The recommended policy on columns of 3 boxes: sample, its first frame.
    EXPECT_EQ(c["balanced_policy"], "sample");
    EXPECT_EQ(c["balanced_recommended"], true);
    const double sampled = report(args + " --balance sample", "sa.json")["render_time_ns"];
    EXPECT_LT(sampled, none);
    EXPECT_EQ(c["balanced_frame"], 1);
    EXPECT_EQ(c["unbalanced_ns"].get<double>(), none);
    EXPECT_EQ(c["balanced_ns"].get<double>(), sampled);
    EXPECT_DOUBLE_EQ(c["ratio"].get<double>(), sampled / none);
    // One frame of resplit is one frame of slide; one frame of measured
    // keeps the starting split: the unbalanced frame, to the picosecond.
    EXPECT_EQ(report(args + " --balance resplit", "r.json")["render_time_ns"], slide["render_time_ns"]);
    const json measured = report(args + " --balance measured", "d.json");
    EXPECT_EQ(measured["render_time_ns"].get<double>(), none);
    EXPECT_EQ(measured["balance"]["slides"], 0);
    EXPECT_GT(slide["balance"]["slides"].get<int>(), 0);
    // So where the recommended policy is measured (columns of more than 8
    // boxes) a single frame is compared with its second frame: re-split from
    // where the first measured the work.
    const std::string longArgs = std::string(kSmall) + " --mesh-dims 9x1x1";
    const Outcome l = run(longArgs + " --image '' --report " + (dir_ / "l.json").string());
    ASSERT_EQ(l.code, 0) << l.err;
    const json longReport = json::parse(slurp(dir_ / "l.json"));
    const json& lc = longReport["comparison"];
    const double longNone = report(longArgs + " --balance none", "ln.json")["render_time_ns"];
    const double second = report(longArgs + " --balance measured --frames 2", "d2.json")["render_time_ns"];
    EXPECT_EQ(lc["unbalanced_ns"].get<double>(), longNone);
    EXPECT_EQ(lc["balanced_policy"], "measured");
    EXPECT_EQ(lc["balanced_recommended"], true);
    EXPECT_EQ(lc["balanced_frame"], 2);
    EXPECT_EQ(lc["balanced_ns"].get<double>(), second);
    EXPECT_NE(l.out.find("this run: no balancing (none); the comparison run: balancing with measured (the recommended "
                         "policy), frame 2"), std::string::npos) << l.out;
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
    EXPECT_NE(o.out.find("this run: no balancing (none); the comparison run: balancing with sample (the recommended "
                         "policy)\n"), std::string::npos) << o.out;
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
    // The recommended policy (sample on these columns of 4 boxes) balances
    // its first frame from a sample of it; slide, the paper's rule within a
    // frame, is held there by its guard.
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

// The same cases in steady state: the fourth frame of the recommended
// policy (sample) against the fourth frame without balancing, and no frame
// of the sequence slower than the unbalanced frame by 2 %.
TEST_P(NeverHurts, DefaultPolicyInSteadyStateLosesAtMostTwoPercent) {
    const std::string along = " --eye=-1.3,0.5,0.5 --look-at=0.5,0.5,0.5 --fov 50";
    const std::string flags = std::string(" --size 128x128 --balance recommended --frames 4 ") + GetParam().flags;
    const std::string args = (std::string(GetParam().name) == "view_across" ? "" : along) + flags;
    const Outcome o = run(args + " -q --image '' --report " + (dir_ / "r.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json r = json::parse(slurp(dir_ / "r.json"));
    ASSERT_EQ(r["frames"].size(), 4u);
    EXPECT_EQ(r["comparison"]["balanced_policy"], "sample");
    EXPECT_LE(r["comparison"]["ratio"].get<double>(), 1 / 0.98) << r["comparison"].dump();
    const double none = r["comparison"]["unbalanced_ns"].get<double>();
    for (const json& f : r["frames"])  // no frame of the sequence, the first included
        EXPECT_LE(f["render_time_ns"].get<double>(), none / 0.98) << f.dump();
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
        // (no error: the baseline and the balancing comparison ran; their policies share no faces)
        const json r = reportWithImage(procedural + flags, image);
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

// --start-mix moves where median and sample start, and only theirs: the
// report echoes it and the planes differ, the image does not, the
// reference runs (which balance otherwise) still run, and with a policy
// that starts uniform it is one line and exit 2.
TEST_F(Rtsim, StartMixMovesOnlyAnObjectStartsPlanes) {
    const std::string procedural = " --size 24x24 --mesh 3 --spheres 60 --concentration 0.3 -q";
    auto start = [&](const std::string& flags, const std::string& image) {
        const json r = reportWithImage(procedural + flags, image);  // (no error: the reference runs ran)
        EXPECT_TRUE(r.contains("baseline") && r.contains("comparison"));
        return std::make_pair(r["config"]["balance"]["start_mix"].get<double>(),
                              r["boundaries"][0]["history"][0][1].get<double>());
    };
    const auto objects = start(" --balance median", "median.png");
    const auto mixed = start(" --balance median --start-mix 0.4", "mixed.png");
    EXPECT_EQ(objects.first, 1.0);
    EXPECT_EQ(mixed.first, 0.4);
    // auto, for sample: on the default machine a test costs less than a tenth
    // of a hop (10 against 212 ns), so half by the length, every column at
    // the same planes; with tests of 1 us, the objects, each column its own.
    for (const auto& [costs, mix, why] : {std::tuple{"", 0.5, "a tenth of a ray's hop"},
                                          std::tuple{" --cost-sphere 1us", 1.0, "a ray's hop"}}) {
        const json r = report(procedural + " --balance sample --no-baseline" + costs);
        EXPECT_EQ(r["config"]["balance"]["start_mix"].get<double>(), mix) << costs;
        const std::string said = r["config"]["balance"].value("start_mix_auto", "");
        EXPECT_NE(said.find(why), std::string::npos) << said;
        // and --sample-end auto by the same costs: credit where the objects are the work
        EXPECT_EQ(r["config"]["balance"]["sample_end"], mix == 1.0 ? "credit" : "generated") << costs;
        EXPECT_NE(r["config"]["balance"].value("sample_end_auto", "").find(why), std::string::npos) << costs;
        std::map<int, std::set<double>> starts;  // boundary index: where the columns start it
        for (const json& b : r["boundaries"]) starts[b["index"]].insert(b["history"][0][1].get<double>());
        for (const auto& [k, at] : starts) EXPECT_EQ(at.size() == 1, mix == 0.5) << k << costs;
    }
    EXPECT_GT(std::abs(mixed.second - objects.second), 0.01) << "the first plane did not move";
    EXPECT_EQ(slurp(dir_ / "mixed.png"), slurp(dir_ / "median.png"));
    expectBad(procedural + " --balance slide --start-mix 0.4", "--start-mix");
    expectBad(procedural + " --balance median --start-mix 1.5", "--start-mix");
    expectBad(procedural + " --balance sample --start-mix nan", "got 'nan'");
    expectBad(procedural + " --balance sample --start-mix '0.5\n'", "got '0.5\\n'");  // (one line, the newline escaped)
    expectBad(procedural + " --balance slide --start-mix 1", "--start-mix");  // (given, even at median's mix)
    expectBad(procedural + " --balance median --start-mix 0.4 --boundaries-from " + (dir_ / "r.json").string(),
              "--start-mix");  // (it would start elsewhere)
    expectBad(procedural + " --balance sample --sample-end credit --boundaries-from " + (dir_ / "r.json").string(),
              "--sample-end");  // (no sample to end)
    expectBad(procedural + " --balance slide --sample-end credit", "--sample-end");
    expectBad(procedural + " --balance sample --sample-end soon", "--sample-end");
    // and auto, where the frame starts elsewhere, chooses nothing and says nothing of a mix
    const json carried = report(procedural + " --balance sample --no-baseline --boundaries-from " + (dir_ / "r.json").string(), "c.json");
    EXPECT_EQ(carried["config"]["balance"]["start_mix"], "auto");
    EXPECT_FALSE(carried["config"]["balance"].contains("start_mix_auto"));
    EXPECT_EQ(carried["config"]["balance"]["sample_end"], "generated");  // (nor of an end: no sample)
    EXPECT_FALSE(carried["config"]["balance"].contains("sample_end_auto"));
    // auto is taken by every policy (chosen only for sample), and the two values given stay given
    EXPECT_EQ(report(procedural + " --balance slide --sample-end credit --sample-end auto --no-baseline", "s.json")
                  ["config"]["balance"]["sample_end"],
              "generated");  // (the last one given counts: no credit left behind for slide to refuse)
    EXPECT_EQ(report(procedural + " --balance sample --sample-end generated --no-baseline --cost-sphere 1us", "g.json")
                  ["config"]["balance"]["sample_end"],
              "generated");
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

// --start-mix auto weighs the half start's long boxes on their links
// (balance/start_links.h): spheres crowded at one end of the axis, viewed
// across it, 5x5x5. At 400 MB/s the half start's long box would generate
// twice the uniform split's primary rays, all out on one link: auto starts
// uniform, says why, and the first frame does not lose, where the half
// start given by hand loses by over 20 %. At 1 GB/s the links keep up and
// auto keeps the half start, which gains.
TEST_F(Rtsim, SampleStartsUniformWhereTheHalfStartsLongBoxWouldFloodItsLink) {
    const std::string across = " --spheres 1000 --radius 0.02 --seed 1 --axis x --concentration 0.125 "
                               "--eye=0.5,-1.6,0.5 --look-at=0.5,0.5,0.5 --fov 40 --mesh 5 --size 64x64 -q --balance sample";
    auto firstFrame = [&](const std::string& flags) {
        const json r = reportWithImage(across + flags, "a.png");
        return std::make_tuple(r["config"]["balance"]["start_mix"].get<double>(),
                               r["config"]["balance"].value("start_mix_auto", ""), r["comparison"]["ratio"].get<double>());
    };
    const auto [slowMix, slowWhy, slow] = firstFrame(" --link-bandwidth 400MB/s");
    EXPECT_EQ(slowMix, 0.0) << slowWhy;
    EXPECT_NE(slowWhy.find("that link would take over 1.2 times the uniform split's frame"), std::string::npos) << slowWhy;
    EXPECT_LE(slow, 1.02);
    const auto [handMix, handWhy, hand] = firstFrame(" --link-bandwidth 400MB/s --start-mix 0.5");
    EXPECT_EQ(handMix, 0.5);
    EXPECT_GT(hand, 1.2) << "the half start no longer floods its link: the case tests nothing";
    const auto [fastMix, fastWhy, fast] = firstFrame(" --link-bandwidth 1GB/s");
    EXPECT_EQ(fastMix, 0.5) << fastWhy;
    EXPECT_LT(fast, 0.8);
}

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
    // Planes out of order (or a box thinner than this run's --min-thickness, left by a run with a smaller one):
    // bad input naming the file and the flag, exit 2, not a failed run (exit 1, rtsim/run).
    json a = json::parse(slurp(dir_ / "a.json"));
    for (json& b : a["boundaries"]) b["history"].back()[1] = 0.5;  // every plane of a column at one place
    std::ofstream(dir_ / "flat.json") << a.dump();
    const Outcome flat = run(std::string(kSliding) + " -q --image '' --boundaries-from " + (dir_ / "flat.json").string());
    EXPECT_EQ(flat.code, 2) << flat.err;
    EXPECT_NE(flat.err.find("--boundaries-from " + (dir_ / "flat.json").string() + ": start boundaries: column 0, box "),
              std::string::npos) << flat.err;
    EXPECT_NE(flat.err.find("is thinner than the minimum thickness (--min-thickness"), std::string::npos) << flat.err;
}

// Its help says "the same scene, mesh and axis": another scene was taken
// (exit 0, or a box "thinner than the minimum thickness" that named no
// cause). The same scene's bytes under another name are the same scene.
TEST_F(Rtsim, BoundariesFromAnotherSceneIsBadInput) {
    report(std::string(kSliding), "a.json");
    const Outcome o = run(std::string(kSliding) + " --seed 2 -q --image '' --boundaries-from " + (dir_ / "a.json").string());
    EXPECT_EQ(o.code, 2);
    EXPECT_NE(o.err.find("--boundaries-from " + (dir_ / "a.json").string() + ": its run was of another scene: /scene/procedural/seed"),
              std::string::npos) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
    const std::string nff = std::string(RT_SCENE_DIR) + "/balls-1.nff";
    std::filesystem::copy_file(nff, dir_ / "copy.nff");
    const std::string file = " --size 32x32 --mesh 2 --balance measured -q --image '' --scene ";
    report(file + nff, "f.json");
    EXPECT_EQ(run(file + (dir_ / "copy.nff").string() + " --boundaries-from " + (dir_ / "f.json").string()).code, 0);
    std::ofstream(dir_ / "other.nff") << slurp(nff) << "s 0.5 0.5 0.5 0.01\n";
    const Outcome other = run(file + (dir_ / "other.nff").string() + " --boundaries-from " + (dir_ / "f.json").string());
    EXPECT_EQ(other.code, 2);
    EXPECT_NE(other.err.find("another scene"), std::string::npos) << other.err;
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
                          " --link-bandwidth 100MB/s --balance measured --frames 2", "t.json");
    EXPECT_EQ(r["frames"][0]["then"]["next"], "aligned");
    EXPECT_LT(r["frames"][1]["render_time_ns"].get<double>(), r["frames"][0]["render_time_ns"].get<double>());
    // The forecast has since picked the aligned planes there on its own
    // (taking columns' own planes for any edge, tetra-3 frames unchanged).
    // Where the rule decides now: gears-2 at 128x128, N = 4, 100 MB/s,
    // whose second frame took 0.729 of the first on the aligned planes and
    // 0.853 on the columns' own, which any edge would have taken.
    const json g = report(" --scene " + std::string(RT_SCENE_DIR) + "/gears-2.nff --size 128x128 --mesh 4"
                          " --link-bandwidth 100MB/s --balance measured --frames 2", "g.json");
    EXPECT_EQ(g["frames"][0]["then"]["next"], "aligned");
    EXPECT_LT(g["frames"][1]["render_time_ns"].get<double>(), 0.8 * g["frames"][0]["render_time_ns"].get<double>());
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
// built-in scene at 32x32 on 64x1x1, where sample's frame takes 1.78 times
// the unbalanced one though no face moves (its sum, climbing the column
// behind the sample's rays, holds the few rays sent up after it:
// doc/balancing.md, "Long columns"), says which frame and how much; on
// 4x4x4 under measured, where no frame lost, it says converged and no more.
TEST_F(Rtsim, TheSummaryNamesAFrameThatLostBesideConvergedBoundaries) {
    const Outcome lost = run("--size 32x32 --mesh-dims 64x1x1 --balance sample --start-mix 0.5 --image ''");
    ASSERT_EQ(lost.code, 0) << lost.err;
    EXPECT_NE(lost.out.find("boundaries converged, but frame 1 took 1.78"), std::string::npos) << lost.out;
    const Outcome fine = run("--size 64x64 --balance measured --frames 3 --image ''");
    ASSERT_EQ(fine.code, 0) << fine.err;
    EXPECT_NE(fine.out.find("boundaries converged\n"), std::string::npos) << fine.out;
    EXPECT_EQ(fine.out.find(", but frame"), std::string::npos) << fine.out;
}

// The recommended policy on long columns, where moving the planes costs more
// than it saves: on the built-in scene at 64x64 measured's second frame took
// 3.5 times the unbalanced one on 33x1x1, 4.0 on 64x1x1 and 1.37 on 64x2x1
// (issue 61), the planes passed along chains of up to a dozen boxes.
// Counting that (move_forecast.h), no frame is slower than the unbalanced
// one by 2 %. On such columns the recommended policy is measured (sample's
// first frame lost there: config/machine_config.h, kLongestColumnSampled).
TEST_F(Rtsim, TheRecommendedPolicyNeverLosesOnALongColumn) {
    // (and 32 nodes along one axis, x or z)
    for (const char* dims : {"32x1x1", "33x1x1", "64x1x1", "64x2x1", "2x2x32 --axis z"}) {
        SCOPED_TRACE(dims);
        const Outcome o = run(std::string("--size 64x64 --balance recommended --frames 3 -q --image '' --mesh-dims ") + dims +
                              " --report " + (dir_ / "r.json").string());
        ASSERT_EQ(o.code, 0) << o.err;
        const json r = json::parse(slurp(dir_ / "r.json"));
        EXPECT_EQ(r["config"]["balance"]["policy"], "measured");
        EXPECT_NE(r["config"]["balance"].value("recommended", "").find("(more than 8)"), std::string::npos);
        ASSERT_EQ(r["frames"].size(), 3u);
        const double none = r["comparison"]["unbalanced_ns"].get<double>();
        for (const json& f : r["frames"]) EXPECT_LE(f["render_time_ns"].get<double>(), 1.02 * none) << f.dump();
    }
}

// A column of one box has no face along the axis to move: there the
// recommended policy is none, and its frame is the unbalanced one to the
// picosecond (sample there only sent its sample's rays first, and that
// order alone made balls-3 on 64x1x1 along z 1.030 of the unbalanced frame).
TEST_F(Rtsim, TheRecommendedPolicyIsNoneOnColumnsOfOneBox) {
    const std::string args = " --size 32x32 --mesh-dims 4x4x1 --axis z --frames 2";
    const json r = report(args + " --balance recommended", "r.json"), none = report(args + " --balance none", "n.json");
    EXPECT_EQ(r["config"]["balance"]["policy"], "none");
    EXPECT_EQ(r["config"]["balance"].value("recommended", ""), "none: columns of 1 box: no boundary along the axis to move");
    ASSERT_EQ(r["frames"].size(), 2u);
    for (size_t i = 0; i < 2; ++i)
        EXPECT_EQ(r["frames"][i]["render_time_ns"], none["frames"][i]["render_time_ns"]) << i;
    const Outcome o = run(args + " --balance recommended --no-baseline --image ''");  // (the summary says why)
    EXPECT_NE(o.out.find("balancing        none: columns of 1 box: no boundary along the axis to move"), std::string::npos)
        << o.out;
}

// Spheres crowded into less than a sphere's width of the axis, seen across
// it: the half start by the objects cut the crowd into boxes thinner than
// its spheres, each of which still held nearly all of them, and gave the
// image's other half to one long box: the recommended policy's first frame
// took 1.43 of the unbalanced one on the modern machine at f = 0.005 (every
// column at the same planes) and 1.16 on the 1987 machine at f = 0.01 (each
// column its own). Counting the objects a box reaches into, the start is
// the uniform split (initial_split.cpp, heaviestReach).
TEST_F(Rtsim, TheRecommendedPolicyNeverLosesWhereTheSpheresCrowdThinnerThanOne) {
    for (const char* where : {"--concentration 0.005", "--concentration 0.01 --config " RT_CONFIG_DIR "/transputer-1987.conf"}) {
        SCOPED_TRACE(where);
        const Outcome o = run(std::string("--size 128x128 --balance recommended --frames 3 -q --image '' ") + where +
                              " --report " + (dir_ / "r.json").string());
        ASSERT_EQ(o.code, 0) << o.err;
        const json r = json::parse(slurp(dir_ / "r.json"));
        EXPECT_EQ(r["comparison"]["balanced_policy"], "sample");
        ASSERT_EQ(r["frames"].size(), 3u);
        const double none = r["comparison"]["unbalanced_ns"].get<double>();
        for (const json& f : r["frames"]) EXPECT_LE(f["render_time_ns"].get<double>(), 1.02 * none) << f.dump();
    }
}

// A frame that starts where another run left its boundaries still has its
// 1x1x1 baseline: the baseline, one node, starts at no boundaries (it was
// given the mesh's report, refused it, and the summary had no speed-up).
TEST_F(Rtsim, ABaselineIgnoresTheBoundariesItHasNone) {
    const std::string small = " --size 16x16 --mesh 3 --spheres 40 --concentration 0.3 -q --image ''";
    const fs::path from = dir_ / "from.json", r = dir_ / "r.json";
    ASSERT_EQ(run(small + " --balance median --no-baseline --report " + from.string()).code, 0);
    const Outcome o = run(small + " --balance none --boundaries-from " + from.string() + " --report " + r.string());
    EXPECT_EQ(o.code, 0) << o.err;
    EXPECT_EQ(o.err, "");
    EXPECT_TRUE(json::parse(slurp(r)).contains("baseline"));
}

// Where neither re-split frame beat frame 1 and the uniform split is out of
// reach, the sequence polishes the fastest re-split frame's planes only if
// that frame took at most kTrialReach (1.2) times frame 1, else it goes back
// to frame 1 at once: gears-2 on the paper's machine, 8x8x2 along z, 64x64,
// re-split frames of 1.635 and 1.629 times frame 1, and the polish's first
// try took 1.617 times it.
TEST_F(Rtsim, SampleGoesBackToFrameOneWhereItsReSplitsAreBeyondAPolishsReach) {
    const json r = report(" --config " RT_CONFIG_DIR "/paper.conf --scene " + std::string(RT_SCENE_DIR) +
                              "/gears-2.nff --axis z --mesh-dims 8x8x2 --size 64x64 --balance sample --frames 4",
                          "g.json");
    ASSERT_EQ(r["frames"].size(), 4u);
    const double first = r["frames"][0]["render_time_ns"].get<double>();
    for (size_t i : {1, 2}) EXPECT_GT(r["frames"][i]["render_time_ns"].get<double>(), rt::kTrialReach * first) << i;
    EXPECT_EQ(r["frames"][2]["then"]["next"], "frame 1 again") << r["frames"].dump();
    EXPECT_EQ(r["frames"][3]["render_time_ns"], r["frames"][0]["render_time_ns"]);
}

// A move whose faces wait for each other (between_frames.h, ResplitChoice):
// on 33x1x1 on the paper's machine, 1,000 spheres in 5 % of the axis seen
// across it, measured's chain of slabs priced the move at 90.3 ms and the
// move took about 228: frame 2 took 1.632 of the unbalanced frame. Each
// node started when its faces are in place, the move's frame is forecast
// at 267.9 ms against the unbalanced split's 153.1: refused, every frame
// the unbalanced one to the picosecond.
TEST_F(Rtsim, AMoveThatWouldLoseAgainstNotBalancingIsRefused) {
    const std::string args = " --config " RT_CONFIG_DIR "/paper.conf --spheres 1000 --radius 0.02 --axis x --concentration 0.05 "
                             "--eye=0.5,-1.6,0.5 --look-at=0.5,0.5,0.5 --fov 40 --mesh-dims 33x1x1 --size 64x64";
    const json r = report(args + " --balance measured --frames 2", "m.json");
    const double none = report(args + " --balance none", "n.json")["render_time_ns"];
    ASSERT_EQ(r["frames"].size(), 2u);
    const json& then = r["frames"][0]["then"];
    EXPECT_EQ(then["next"], "held") << then.dump();
    ASSERT_TRUE(then.contains("refused")) << then.dump();
    const json& refused = then["refused"];
    EXPECT_TRUE(refused["what"] == "aligned" || refused["what"] == "per column") << then.dump();
    // The chain's price let it through; the handovers did not.
    EXPECT_LT(refused["forecast_ns"].get<double>(), (1 - rt::kMinForecastGain) * then["held_forecast_ns"].get<double>());
    EXPECT_GT(refused["faces_in_place_forecast_ns"].get<double>(),
              (1 + rt::kMinForecastGain) * then["unbalanced_forecast_ns"].get<double>());
    EXPECT_FALSE(then.contains("faces_in_place_forecast_ns")) << then.dump();  // (the planes held's: none)
    for (const json& f : r["frames"]) EXPECT_EQ(f["render_time_ns"].get<double>(), none);
}

// And a move that costs its own frame more than holding, but not more than
// not balancing, is made: it pays in the frames after it. balls-5 on
// 16x16x4 on the paper's machine under sample: frame 2 forecast at 1.26
// times holding, its frame 0.644 of the unbalanced one, then 0.162.
TEST_F(Rtsim, AMoveThatCostsItsFrameButNotAgainstNotBalancingIsMade) {
    const std::string args = " --config " RT_CONFIG_DIR "/paper.conf --scene " + std::string(RT_SCENE_DIR) +
                             "/balls-5.nff --mesh-dims 16x16x4 --size 64x64";
    const json r = report(args + " --balance sample --frames 3", "s.json");
    ASSERT_EQ(r["frames"].size(), 3u);
    const json& then = r["frames"][0]["then"];
    EXPECT_EQ(then["next"], "aligned") << then.dump();
    EXPECT_FALSE(then.contains("refused")) << then.dump();
    const double inPlace = then["faces_in_place_forecast_ns"].get<double>();
    EXPECT_GT(inPlace, then["held_forecast_ns"].get<double>());
    EXPECT_LE(inPlace, (1 + rt::kMinForecastGain) * then["unbalanced_forecast_ns"].get<double>());
    const double first = r["frames"][0]["render_time_ns"];
    EXPECT_LT(r["frames"][1]["render_time_ns"].get<double>(), first);
    EXPECT_LT(r["frames"][2]["render_time_ns"].get<double>(), 0.3 * first);
}

// One try (between_frames.h): the first time sample's forecast says hold,
// a re-split forecast at least 1 % faster (and under the 4 % margin) runs
// once. With the built-in scene's spheres everywhere, across the axis,
// frame 3 gained on frame 2 so. Once only (trying at every hold, this
// sequence tries four times), and never under measured.
TEST_F(Rtsim, SampleTriesOnceAReSplitTheMarginHides) {
    const std::string args = " --size 128x128 --frames 5 --concentration 1";
    const json r = report(args + " --balance sample", "s.json");
    ASSERT_EQ(r["frames"].size(), 5u);
    const json& then = r["frames"][1]["then"];
    EXPECT_EQ(then["next"], "one try: aligned") << r["frames"].dump();
    const double gain = 1 - then["forecast_ns"].get<double>() / then["held_forecast_ns"].get<double>();
    EXPECT_GE(gain, 0.01);
    EXPECT_LT(gain, 0.04);
    EXPECT_LT(r["frames"][2]["render_time_ns"].get<double>(), r["frames"][1]["render_time_ns"].get<double>());
    int tries = 0;
    for (const json& f : r["frames"]) tries += f.value("then", json::object()).value("next", "").rfind("one try", 0) == 0;
    EXPECT_EQ(tries, 1) << r["frames"].dump();
    const json m = report(args + " --balance measured", "m.json");  // (held: the loop refers into it)
    for (const json& f : m["frames"])
        EXPECT_NE(f.value("then", json::object()).value("next", "").rfind("one try", 0), 0u) << f.dump();
}

// A sequence under sample whose two re-split frames do not beat the first
// tries, for one frame, the uniform split: the unbalanced frame itself, to
// the picosecond. It held sample's start there before, which on the paper's
// machine across the axis at f = 1 is slower than not balancing (1.024 of
// the unbalanced frame at N = 3: doc/balancing.md, "The recommended policy").
// (Across the axis at N = 2, f = 1: frames of 0.965, 0.968 and 0.968 of the
// unbalanced frame; the trial forecast at 1.03 of frame 1.)
// The two tests of sample's trial: four frames under sample on the paper's
// machine across the axis, and the unbalanced frame's time.
class SampleTrial : public Rtsim {
protected:
    std::pair<json, double> sequence(int n, const char* concentration, const std::string& more = " --frames 4") {
        const std::string args = " --config " RT_CONFIG_DIR "/paper.conf --spheres 1000 --radius 0.02 --seed 1"
                                 " --size 256x256 --mesh " + std::to_string(n) + " --concentration " + concentration;
        const json r = report(args + " --balance sample" + more, "s.json");
        return {r, report(args + " --balance none", "n.json")["render_time_ns"].get<double>()};
    }
};

TEST_F(SampleTrial, IsTheUnbalancedFrame) {
    const auto [r, none] = sequence(2, "1");
    ASSERT_EQ(r["frames"].size(), 4u);
    EXPECT_EQ(r["frames"][2]["then"]["next"], "the uniform split");
    EXPECT_LE(r["frames"][2]["then"]["start_forecast_ns"].get<double>(),
              rt::kTrialReach * r["frames"][0]["render_time_ns"].get<double>());
    EXPECT_EQ(r["frames"][3]["render_time_ns"].get<double>(), none);
    EXPECT_LT(r["frames"][0]["render_time_ns"].get<double>(), none);  // (so frame 1 again after it)
}

// ... but not where the forecast puts the uniform split far slower than
// frame 1: that frame was lost (the paper's machine across the axis at
// N = 5, f = 1/5: re-split frames of 0.312 and 0.307 of the unbalanced
// frame after a first frame of 0.285, then the unbalanced frame). The
// forecast of the trial is checked against the unbalanced frame run.
TEST_F(SampleTrial, IsSkippedWhereItsForecastPutsItFarBehindFrameOne) {
    const auto [r, none] = sequence(5, "0.2", " --frames 4 --polish-tries 0");  // (by default it polishes: below)
    ASSERT_EQ(r["frames"].size(), 4u);
    const double first = r["frames"][0]["render_time_ns"];
    EXPECT_EQ(r["frames"][2]["then"]["next"], "frame 1 again");
    const double forecast = r["frames"][2]["then"]["start_forecast_ns"];
    EXPECT_GT(forecast, rt::kTrialReach * first);
    EXPECT_NEAR(forecast / none, 1.0, 0.1);  // (3.42 against the 3.51 measured, in frame 1's times)
    EXPECT_EQ(r["frames"][3]["render_time_ns"].get<double>(), first);
    EXPECT_LT(first, 0.3 * none);
}

// --polish-tries auto, the default, is 8 under sample: the same sequence
// tries a move where, with --polish-tries 0, it goes back to frame 1.
TEST_F(SampleTrial, PolishesByDefault) {
    const auto [r, none] = sequence(5, "0.2");
    EXPECT_EQ(r["config"]["balance"]["polish_tries"], rt::kSamplePolishTries);
    EXPECT_EQ(r["frames"][2]["then"]["next"], "a move tried");
    EXPECT_LT(r["frames"][3]["render_time_ns"].get<double>(), none);
}

// The summary names the frames that tried a move and counts those kept:
// counted here as the try frames faster than every frame since the one
// the polish started from (the frame before the first try).
TEST_F(SampleTrial, TheSummaryCountsThePolishsMoves) {
    const std::string args = " --config " RT_CONFIG_DIR "/paper.conf --spheres 1000 --radius 0.02 --seed 1 --size 128x128"
                             " --mesh 5 --concentration 0.2 --balance sample --frames 14 --polish-tries 8 --no-baseline --image '' --report " +
                             (dir_ / "p.json").string();
    const Outcome o = run(args);
    ASSERT_EQ(o.code, 0) << o.err;
    const json r = json::parse(slurp(dir_ / "p.json"));
    int first = 0, last = 0, kept = 0;
    double best = 0;
    for (int k = 1; k < int(r["frames"].size()); ++k) {
        if (r["frames"][k - 1]["then"]["next"] != "a move tried") continue;
        if (!first) best = r["frames"][k - 1]["render_time_ns"].get<double>();
        first = first ? first : k + 1;
        last = k + 1;
        const double t = r["frames"][k]["render_time_ns"];
        kept += t < best;
        best = std::min(best, t);
    }
    ASSERT_GT(last, first);
    const std::string line = "polish           frames " + std::to_string(first) + " to " + std::to_string(last) +
                             " tried a move of the planes held each, " + std::to_string(kept) + " of " +
                             std::to_string(last - first + 1) + " faster and kept (--polish-tries 8)\n";
    EXPECT_NE(o.out.find(line), std::string::npos) << o.out;
}

// With --polish-tries, the same sequence polishes the fastest re-split
// frame's planes first (between_frames.h, "Polish"), and goes back to
// frame 1 only if no polished frame beat it. (Measured at 8 tries and 14
// frames: the polish reached 1.014 of the best static split, frame 1 was
// 1.068: doc/balancing.md, "Polish".)
TEST_F(SampleTrial, PolishesTheReSplitFramesBeforeGoingBackToFrameOne) {
    const auto [r, none] = sequence(5, "0.2", " --frames 7 --polish-tries 3");
    ASSERT_EQ(r["frames"].size(), 7u);
    const double first = r["frames"][0]["render_time_ns"];
    EXPECT_EQ(r["frames"][2]["then"]["next"], "a move tried");
    EXPECT_GT(r["frames"][2]["then"]["start_forecast_ns"].get<double>(), rt::kTrialReach * first);
    double polished = 1e300;  // the fastest of the frames that tried a move, and of the one they started from
    for (int k = 1; k < 6; ++k) polished = std::min(polished, r["frames"][k]["render_time_ns"].get<double>());
    const json& last = r["frames"][5]["then"];
    if (polished < first) {
        EXPECT_EQ(last["next"], "held");
        EXPECT_LT(r["frames"][6]["render_time_ns"].get<double>(), first);
    } else {
        EXPECT_EQ(last["next"], "frame 1 again");
        EXPECT_EQ(r["frames"][6]["render_time_ns"].get<double>(), first);
    }
    EXPECT_LT(first, 0.3 * none);
}

// The SPD balls along z, on the 1987 machine: the eye looks down from above
// the axis's far end, so the top nodes generate every primary ray.
//  - Under --sample-end generated the gather climbed from the lowest nodes
//    before the sample's rays came down, and the planes followed the top
//    boxes' work alone: frame 1 took 4.01 of the unbalanced frame. auto
//    waits for the credit there (sample_end.h).
//  - Between frames, a move that gave the bottom box (the floor's, 12 wide)
//    the lower half of the sphere flake spread that box's grid over the
//    floor: its cells grew 4 times, and `measured`'s frame 3 took 1.60 of
//    the unbalanced frame where the forecast said 0.31. The forecast counts
//    such a grid (FrameForecast, kCoarser) and holds.
TEST_F(Rtsim, AlongZTheSpdBallsNeverLoseThoughTheTopNodesGenerateEveryRay) {
    for (const char* policy : {"recommended", "measured"}) {
        SCOPED_TRACE(policy);
        const Outcome o = run(" --scene " + std::string(RT_SCENE_DIR) + "/balls-4.nff --config " RT_CONFIG_DIR
                              "/transputer-1987.conf --size 64x64 --mesh 4 --axis z --frames 3 -q --image '' --balance " +
                              policy + " --report " + (dir_ / "r.json").string());
        ASSERT_EQ(o.code, 0) << o.err;
        const json r = json::parse(slurp(dir_ / "r.json"));
        if (std::string(policy) == "recommended") {
            EXPECT_NE(r["config"]["balance"].value("sample_end_auto", "").find("only the columns' top nodes generate"),
                      std::string::npos);
        }
        ASSERT_EQ(r["frames"].size(), 3u);
        const double none = r["comparison"]["unbalanced_ns"].get<double>();
        for (const json& f : r["frames"]) EXPECT_LE(f["render_time_ns"].get<double>(), 1.02 * none) << f.dump();
    }
}

// balls-2 along z on the modern machine (91 spheres, a few in each box):
// the re-split after the sample's frame gave the bottom box the floor and
// the lowest spheres of the box above, whose grid was 4 times finer, and
// its sphere tests grew 5.4 times (at 128x128 frame 2 took 1.317 of the
// unbalanced frame, against 1.044 for frame 1; here 1.095 times frame 1).
// The spheres it took (9 at 128x128) were fewer than the count's least
// once was (64): the count needs only 8 (FrameForecast::coarsening,
// kLeastKept), and the move is held.
TEST_F(Rtsim, AlongZTheReSplitCountsTheCoarserGridOfAFewSpheres) {
    const Outcome o = run(" --scene " + std::string(RT_SCENE_DIR) + "/balls-2.nff --config " RT_CONFIG_DIR
                          "/modern.conf --size 64x64 --mesh 4 --axis z --frames 2 -q --image '' --no-baseline"
                          " --balance recommended --report " + (dir_ / "r.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json r = json::parse(slurp(dir_ / "r.json"));
    ASSERT_EQ(r["frames"].size(), 2u);
    EXPECT_EQ(r["frames"][0]["then"]["next"], "held") << r["frames"][0].dump();
    EXPECT_LE(r["frames"][1]["render_time_ns"].get<double>(), 1.02 * r["frames"][0]["render_time_ns"].get<double>());
}
