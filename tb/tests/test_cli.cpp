// rtref as a user runs it: outputs, stats JSON, determinism, and a one-line
// error with exit code 2 for each kind of bad input.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "renderer.h"
#include "scenes.h"

namespace fs = std::filesystem;

namespace {

struct Outcome {
    int code;
    std::string out, err;
};

std::string slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

class Rtref : public testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("rtref_test_" + std::to_string(::getpid()) + "_" +
                                            testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    Outcome run(const std::string& args) {
        const fs::path out = dir_ / "stdout", err = dir_ / "stderr";
        const std::string cmd = std::string(RTREF_EXE) + " " + args + " >" + out.string() + " 2>" + err.string();
        const int status = std::system(cmd.c_str());
        return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
    }
    void expectBad(const std::string& args, const std::string& mention) {
        SCOPED_TRACE(args);
        const Outcome r = run(args);
        EXPECT_EQ(r.code, 2);
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find(mention), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "x.png"));
    }
    std::string scene(const std::string& n) { return std::string(RT_SCENE_DIR) + "/" + n + ".nff"; }
    fs::path dir_;
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

TEST_F(Rtref, BadInputGivesOneLineAndExit2) {
    const std::string o = " -o " + (dir_ / "x.png").string();
    expectBad("/nonexistent.nff" + o, "/nonexistent.nff");
    expectBad(scene("balls-1") + " --size 0x10" + o, "--size");
    expectBad(scene("balls-1") + " --size 10by10" + o, "--size");
    expectBad(scene("balls-1") + " --max-depth -1" + o, "--max-depth");
    expectBad(scene("balls-1") + " --threads 0" + o, "--threads");
    expectBad(scene("balls-1") + " --frobnicate" + o, "--frobnicate");
    expectBad("--concentration 0" + o, "--concentration");
    expectBad("--axis w" + o, "--axis");
    std::ofstream(dir_ / "bad.nff") << "v\nfrom 0 0 0\nat 0 0 1\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\ns 0 0 5 q\n";
    expectBad((dir_ / "bad.nff").string() + o, "bad.nff:8: expected a number for sphere radius, got 'q'");
}
