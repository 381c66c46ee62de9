// rtref as a user runs it: outputs, stats JSON, determinism, and a one-line
// error with exit code 2 for each kind of bad input.
#include <algorithm>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "renderer.h"
#include "command_test.h"
#include "scenes.h"

using namespace rt::test;

namespace {

class Rtref : public CommandTest {
protected:
    Rtref() : CommandTest(RTREF_EXE) {}
    void expectBadNoImage(const std::string& args, const std::string& mention) {
        expectBad(args, mention);
        EXPECT_FALSE(fs::exists(dir_ / "x.png"));
    }
};

}  // namespace

TEST_F(Rtref, WritesPngAndStatsMatchingTheLibrary) {
    const Outcome r = run(scene("balls-2") + " -o " + (dir_ / "a.png").string() + " --size 40x30 --stats " +
                      (dir_ / "s.json").string());
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string png = slurp(dir_ / "a.png");
    ASSERT_GT(png.size(), 8u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    const auto j = nlohmann::json::parse(slurp(dir_ / "s.json"));
    for (const char* k : {"primary_rays", "primary_hits", "shadow_rays", "shadow_hits", "secondary_rays",
                          "secondary_hits", "intersection_tests", "voxel_steps", "wall_s"})
        EXPECT_TRUE(j.contains(k)) << k;
    // The same counts as the library gives for the same render.
    const rt::Scene s = rt::test::spd("balls-2");
    rt::RenderOptions o;
    o.width = 40;
    o.height = 30;
    const rt::Counters c = rt::render(s, rt::Partition::whole(s), o).counters;
    EXPECT_EQ(j["primary_rays"], 1200u);
    EXPECT_EQ(j["primary_hits"], c.primaryHits);
    EXPECT_EQ(j["shadow_rays"], c.shadowRays);
    EXPECT_EQ(j["shadow_hits"], c.shadowHits);
    EXPECT_EQ(j["secondary_rays"], c.secondaryRays);
    EXPECT_EQ(j["intersection_tests"], c.intersectionTests());
    EXPECT_EQ(j["voxel_steps"], c.voxelSteps);
}

TEST_F(Rtref, OutputsAreWrittenWholeWithNothingElseBesideThem) {
    // Each output goes to a temporary file beside it and is renamed at the
    // end (output_file.h): after the run the folder holds exactly the two.
    ASSERT_EQ(run("--spheres 50 --size 16x16 -o " + (dir_ / "a.png").string() + " --stats " + (dir_ / "s.json").string())
                  .code,
              0);
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_))
        if (e.path().filename() != "stdout" && e.path().filename() != "stderr") names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"a.png", "s.json"}));
    EXPECT_EQ(fs::status(dir_ / "a.png").permissions() & fs::perms::others_read, fs::perms::others_read);
}

TEST_F(Rtref, SameInputsSameBytes) {
    ASSERT_EQ(run(scene("rings-2") + " --size 48x48 -o " + (dir_ / "a.png").string()).code, 0);
    ASSERT_EQ(run(scene("rings-2") + " --size 48x48 --threads 2 -o " + (dir_ / "b.png").string()).code, 0);
    EXPECT_EQ(slurp(dir_ / "a.png"), slurp(dir_ / "b.png"));
    ASSERT_EQ(run("--spheres 50 --size 32x32 -o " + (dir_ / "c.png").string()).code, 0);
    ASSERT_EQ(run("--spheres 50 --size 32x32 -o " + (dir_ / "d.png").string()).code, 0);
    ASSERT_EQ(run("--spheres 50 --size 32x32 --seed 2 -o " + (dir_ / "e.png").string()).code, 0);
    EXPECT_EQ(slurp(dir_ / "c.png"), slurp(dir_ / "d.png"));
    EXPECT_NE(slurp(dir_ / "c.png"), slurp(dir_ / "e.png"));
}

TEST_F(Rtref, VectorFlagsTakeNegativeNumbersInBothForms) {
    // A camera below the cube's centre, given with spaces and with commas.
    ASSERT_EQ(run("--spheres 50 --size 24x24 --eye 0.5 -1.6 0.2 -o " + (dir_ / "a.png").string()).code, 0);
    ASSERT_EQ(run("--spheres 50 --size 24x24 --eye=0.5,-1.6,0.2 -o " + (dir_ / "b.png").string()).code, 0);
    ASSERT_EQ(run("--spheres 50 --size 24x24 -o " + (dir_ / "c.png").string()).code, 0);
    EXPECT_EQ(slurp(dir_ / "a.png"), slurp(dir_ / "b.png"));
    EXPECT_NE(slurp(dir_ / "a.png"), slurp(dir_ / "c.png"));
}

TEST_F(Rtref, BadInputGivesOneLineAndExit2) {
    const std::string o = " -o " + (dir_ / "x.png").string();
    expectBadNoImage("/nonexistent.nff" + o, "/nonexistent.nff");
    expectBadNoImage(scene("balls-1") + " --size 0x10" + o, "--size");
    expectBadNoImage(scene("balls-1") + " --size 10by10" + o, "--size");
    expectBadNoImage(scene("balls-1") + " --max-depth -1" + o, "--max-depth");
    expectBadNoImage(scene("balls-1") + " --threads 0" + o, "--threads");
    expectBadNoImage(scene("balls-1") + " --frobnicate" + o, "--frobnicate");
    expectBadNoImage("--concentration 0" + o, "--concentration");
    expectBadNoImage("--axis w" + o, "--axis");
    expectBadNoImage("--eye 1 2" + o, "--eye");
    expectBadNoImage("--eye 1,2,3,4" + o, "--eye");  // (rtsim, whose flags take their last value, took 2,3,4)
    expectBadNoImage("--light 0,0" + o, "--light");
    expectBadNoImage("--eye nan,0,0" + o, "--eye");
    expectBadNoImage("--eye inf,0,0" + o, "--eye");
    expectBadNoImage("--look-at 0,0,-inf" + o, "--look-at");
    expectBadNoImage("--light nan,0,0" + o, "--light");
    // Beyond 1e9 (an NFF file's limit too): an eye at 1e200 rendered the background with exit 0.
    expectBadNoImage("--eye 1e200,0.5,0.5" + o, "--eye: expected a number of magnitude at most 1e9, got '1e200'");
    expectBadNoImage("--light 0,-2e9,0" + o, "--light: expected a number of magnitude at most 1e9");
    // CLI11 reads integers in C's base 0: 010 was 8 threads.
    expectBadNoImage("--size 8x8 --threads 010" + o, "--threads: expected a decimal integer, got '010'");
    expectBadNoImage("--size 8x8 --max-depth 0x2" + o, "--max-depth: expected a decimal integer");
    // A scene's name goes into the stats (JSON): bytes that are not UTF-8 are
    // refused before the render (they failed as the stats were written).
    const std::string bytes = (dir_ / "\xff.nff").string();
    std::ofstream(bytes) << "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.01\nresolution 8 8\ns 0 0 0 1\n";
    expectBadNoImage(bytes + o + " --stats " + (dir_ / "s.json").string(), "the scene file's name is not valid UTF-8");
    EXPECT_FALSE(fs::exists(dir_ / "s.json"));
    // Outputs that cannot be written: found before the render, and the
    // image is not left behind when the stats cannot be written.
    expectBad("--size 8x8 -o /nonexistent/x.png", "--output: /nonexistent/x.png: no such folder");
    // 108 GiB at the least: refused up front (it died of bad_alloc naming nothing).
    expectBadNoImage("--size 65536x65536" + o, "--size 65536x65536: needs at least");
    expectBad("--size 8x8 -o " + dir_.string(), "is a folder");
    expectBadNoImage("--size 8x8 --stats /proc/s.json" + o, "--stats: /proc/s.json");
    std::ofstream(dir_ / "bad.nff") << "v\nfrom 0 0 0\nat 0 0 1\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\ns 0 0 5 q\n";
    expectBadNoImage((dir_ / "bad.nff").string() + o, "bad.nff:8: expected a number for sphere radius, got 'q'");
}
