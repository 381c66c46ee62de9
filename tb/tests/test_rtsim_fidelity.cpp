// rtsim end to end at the fidelity rungs (doc/fidelity.md): --fidelity
// express renders the same image, and --max-error picks a rung within the
// error asked for, says how, and keeps to the exact model where it must.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "rtsim_test.h"

using nlohmann::json;
using namespace rt::test;

namespace {
const std::string kBalls4 = " --scene " + std::string(RT_SCENE_DIR) + "/balls-4.nff --size 256x256 --mesh 16";
}  // namespace

// balls-4 at 256x256 on 16x16x16 (16 pixels a node, the fewest it
// calibrates at): calibration frames of 16x16 pixels (every 16th of every
// 16th row: at least 256 pixels and a 256th), in the machine that then
// renders the frame, exact and then at the coarser rungs (through, then
// express), the coarsest first, until one is within half the error; the rung chosen is
// within the error on the frame itself, the image is the exact run's, the
// report and the summary say how it chose, and the same inputs choose the
// same rung.
TEST_F(Rtsim, MaxErrorPicksARungWithinItAndSaysHow) {
    ASSERT_EQ(run(kBalls4 + " --no-baseline -q --image " + (dir_ / "e.png").string() + " --report " + (dir_ / "exact.json").string()).code, 0);
    const json exact = json::parse(slurp(dir_ / "exact.json"));
    const std::string args = kBalls4 + " --max-error 1%";
    const Outcome o = run(args + " --no-baseline --image " + (dir_ / "m.png").string() + " --report " + (dir_ / "m.json").string());
    ASSERT_EQ(o.code, 0) << o.err;
    const json m = json::parse(slurp(dir_ / "m.json"));
    EXPECT_EQ(slurp(dir_ / "m.png"), slurp(dir_ / "e.png"));
    const json& f = m["fidelity"];
    EXPECT_EQ(f["rung"], m["config"]["fidelity"]["rung"]);
    EXPECT_EQ(m["config"]["fidelity"]["max_error"], 0.01);
    EXPECT_EQ(f["calibration"]["size"], "16x16");
    EXPECT_EQ(f["calibration"]["pixel_stride"], 16);
    const json& tried = f["calibration"]["rungs"];
    ASSERT_GE(tried.size(), 1u);
    EXPECT_EQ(tried[0]["rung"], "through");  // (the coarsest of the two it tries: doc/fidelity.md)
    if (tried.size() > 1) {
        EXPECT_EQ(tried[1]["rung"], "express");
    }
    for (size_t i = 0; i + 1 < tried.size(); ++i) EXPECT_FALSE(tried[i]["within"].get<bool>()) << "tried on past " << tried[i]["rung"];
    EXPECT_EQ(tried.back()["rung"], f["rung"]);
    for (const json& r : tried) {
        const double err = std::fabs(r["render_time_ns"].get<double>() / f["calibration"]["exact"]["render_time_ns"].get<double>() - 1);
        EXPECT_NEAR(r["error"].get<double>(), err, 1e-12);
        EXPECT_EQ(r["within"].get<bool>(), err <= 0.005) << r["rung"];
        if (r["rung"] == f["rung"]) {
            EXPECT_TRUE(r["within"].get<bool>());
            EXPECT_LT(r["events"].get<double>(), f["calibration"]["exact"]["events"].get<double>());
        }
    }
    EXPECT_NE(f["rung"], "exact");  // (a coarser rung is within it here)
    EXPECT_LE(std::fabs(m["render_time_ns"].get<double>() / exact["render_time_ns"].get<double>() - 1), 0.01);
    // The frame, rendered by the machine that ran the calibration frames, is the rung's own to the ps.
    const json alone = report(kBalls4 + " --fidelity " + f["rung"].get<std::string>(), "alone.json");
    EXPECT_EQ(m["render_time_ns"], alone["render_time_ns"]);
    EXPECT_EQ(m["totals"], alone["totals"]);
    EXPECT_GT(m["wall_clock"]["calibration_s"].get<double>(), 0.0);
    EXPECT_NE(o.out.find("fidelity         " + f["rung"].get<std::string>() + ", chosen for --max-error 1 %"), std::string::npos) << o.out;
    json again = report(args, "again.json"), first = m;
    dropWall(again);
    dropWall(first);
    EXPECT_EQ(again["fidelity"], first["fidelity"]);
    EXPECT_EQ(again["render_time_ns"], first["render_time_ns"]);
}

// A sequence after the calibration: its frames are those the chosen rung
// renders without one, and frame 1 starts at 0 on the frames' clock,
// though the calibration frames ran before it in the same machine.
TEST_F(Rtsim, MaxErrorFramesAreTheRungsOwnFromZero) {
    const std::string seq = " --frames 2 --eye-step 0.01,0,0";
    const json m = report(kBalls4 + seq + " --max-error 1%", "m.json");
    ASSERT_TRUE(m["fidelity"].contains("calibration"));
    const json alone = report(kBalls4 + seq + " --fidelity " + m["fidelity"]["rung"].get<std::string>(), "alone.json");
    ASSERT_EQ(m["frames"].size(), 2u);
    EXPECT_EQ(m["frames"][0]["starts_at_ns"], 0.0);
    EXPECT_EQ(m["frames"], alone["frames"]);
    EXPECT_EQ(m["totals"], alone["totals"]);
}

// Where the timing steers the boundaries, where the image is too small to
// calibrate on less of it, on a mesh too small for a rung to pay for its
// calibration, and where the frame is too short for it (fewer than 16
// pixels a node: 255x256 on 16x16x16 is one column short), the exact model,
// without a calibration.
TEST_F(Rtsim, MaxErrorKeepsToExactWhereItMust) {
    const json slide = report(" --scene " + std::string(RT_SCENE_DIR) + "/balls-4.nff --size 64x64 --mesh 16 --balance slide --max-error 2%");
    EXPECT_EQ(slide["config"]["fidelity"]["rung"], "exact");
    EXPECT_FALSE(slide["fidelity"].contains("calibration"));
    EXPECT_NE(slide["fidelity"]["why"].get<std::string>().find("timing steers"), std::string::npos);
    const json small = report(" --scene " + std::string(RT_SCENE_DIR) + "/balls-4.nff --size 24x24 --mesh 16 --max-error 2%");
    EXPECT_EQ(small["config"]["fidelity"]["rung"], "exact");
    EXPECT_NE(small["fidelity"]["why"].get<std::string>().find("too small"), std::string::npos);
    EXPECT_FALSE(small["wall_clock"].contains("calibration_s"));
    const json few = report(" --scene " + std::string(RT_SCENE_DIR) + "/balls-4.nff --size 64x64 --mesh 8 --max-error 2%");
    EXPECT_EQ(few["config"]["fidelity"]["rung"], "exact");
    EXPECT_NE(few["fidelity"]["why"].get<std::string>().find("4096 nodes"), std::string::npos);
    const json shortFrame = report(" --scene " + std::string(RT_SCENE_DIR) + "/balls-4.nff --size 255x256 --mesh 16 --max-error 2%");
    EXPECT_EQ(shortFrame["config"]["fidelity"]["rung"], "exact");
    EXPECT_NE(shortFrame["fidelity"]["why"].get<std::string>().find("16 pixels per node"), std::string::npos);
    EXPECT_FALSE(shortFrame["wall_clock"].contains("calibration_s"));
}

// Nonsense values and rungs that do not apply: one line naming the flag, exit 2.
TEST_F(Rtsim, BadFidelityFlagsAreOneLineErrors) {
    for (const std::string bad : {" --max-error 0", " --max-error 100%", " --max-error 1.5", " --max-error abc", " --max-error 2%%",
                                   " --max-error 1% --fidelity express", " --max-error 1% --quantum 10us",
                                   " --fidelity express --balance slide", " --fidelity express --ray-batch 4", " --fidelity fast"}) {
        const Outcome o = run(kBalls4 + bad + " --no-baseline -q --image ''");
        EXPECT_EQ(o.code, 2) << bad;
        const std::string flag = bad.find("--max-error") != std::string::npos ? "--max-error" : "--fidelity";
        EXPECT_NE(o.err.find(flag), std::string::npos) << bad << ": " << o.err;
        EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << bad << ": " << o.err;
    }
    // It names the rung given (it said "--fidelity express or --quantum lookahead", the exact rung's own quantum).
    EXPECT_NE(run(kBalls4 + " --max-error 1% --quantum 10us --no-baseline -q --image ''").err.find("not with --quantum 10us"),
              std::string::npos);
    const Outcome express = run(kBalls4 + " --max-error 1% --fidelity express --no-baseline -q --image ''");
    EXPECT_NE(express.err.find("not with --fidelity express"), std::string::npos) << express.err;
    EXPECT_EQ(express.err.find("lookahead"), std::string::npos) << express.err;
    // And the policy as given: recommended, then what it chose (it said "not --balance sample").
    const Outcome recommended = run(kBalls4 + " --fidelity express --balance recommended --no-baseline -q --image ''");
    EXPECT_EQ(recommended.code, 2);
    EXPECT_NE(recommended.err.find("not --balance recommended ("), std::string::npos) << recommended.err;
}
