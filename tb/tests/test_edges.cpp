// rtsim's edges end to end, as a hostile but fair user meets them
// (doc/robustness.md, "Edges"): a received report that tries to write or
// read where it should not, outputs that are not files of their own, derived
// times past the picosecond counter, stops in start-up, between frames and
// in the reference runs, a scene too big to bin, config files read whole.
// Each run gets its own TMPDIR, so that a temporary left behind is seen.
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <random>
#include <regex>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "command_test.h"

using nlohmann::json;
using namespace rt::test;

namespace {

const char* kSmall = " --spheres 200 --radius 0.04 --size 16x16 --mesh 2";

class Edges : public CommandTest {
protected:
    Edges() : CommandTest("env") {}
    void SetUp() override {
        CommandTest::SetUp();
        fs::create_directories(tmp());
    }
    fs::path tmp() const { return dir_ / "tmp"; }
    // rtsim with `args` in the test's folder (so a relative path a bug lets
    // through lands where the test looks), its temporary files in tmp(),
    // stopped after a minute.
    Outcome rtsim(const std::string& args) {
        return run("TMPDIR=" + tmp().string() + " timeout 60 " + RTSIM_EXE + " " + args, dir_);
    }
    // Bad input: exit 2, one line mentioning `mention`.
    void bad(const std::string& args, const std::string& mention) {
        SCOPED_TRACE(args);
        const Outcome o = rtsim(args);
        EXPECT_EQ(o.code, 2) << o.err;
        EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
        EXPECT_NE(o.err.find(mention), std::string::npos) << o.err;
    }
    // Temporary files anywhere they could be: rtsim's own (tmp()), and
    // outputs' (NAME.incomplete-XXXXXX beside them).
    std::vector<std::string> leftBehind() const {
        std::vector<std::string> out;
        for (const auto& e : fs::recursive_directory_iterator(dir_)) {
            const std::string p = e.path().string();
            if (p.find(".incomplete-") != std::string::npos || e.path().parent_path() == tmp()) out.push_back(p);
        }
        return out;
    }
    void write(const fs::path& p, const std::string& text) const { std::ofstream(p) << text; }
    std::string p(const std::string& name) const { return (dir_ / name).string(); }
    // A report of a small run, to be tampered with.
    json baseReport() {
        const Outcome o = rtsim(std::string(kSmall) + " --no-baseline -q --image '' --report " + p("base.json"));
        EXPECT_EQ(o.code, 0) << o.err;
        return json::parse(slurp(dir_ / "base.json"));
    }
};

// How a run stopped by a signal ended: its exit code, the milliseconds from
// the signal to its end, its standard error.
struct Stopped {
    int code = -1;
    long ms = -1;
    std::string err;
};

class EdgesTimed : public Edges {
protected:
    // rtsim `args` in the background; once the bash condition `ready` holds
    // (within a minute), signal `sig` to it.
    Stopped stopWhen(const std::string& args, const std::string& ready, const std::string& sig) {
        const fs::path err = dir_ / "err", out = dir_ / "timing";
        const std::string script = "TMPDIR=" + tmp().string() + " " + RTSIM_EXE + " " + args + " 2>" + err.string() +
                                   " & p=$!; for i in $(seq 1200); do " + ready + " && break; sleep 0.05; done; "
                                   "t0=$(date +%s%N); kill -" + sig + " $p; wait $p; c=$?; t1=$(date +%s%N); "
                                   "echo $c $(( (t1 - t0) / 1000000 )) >" + out.string();
        std::ofstream(dir_ / "stop.sh") << script << "\n";
        std::system(("bash " + (dir_ / "stop.sh").string()).c_str());
        Stopped s;
        std::istringstream(slurp(out)) >> s.code >> s.ms;
        s.err = withoutSanitizerNoise(slurp(err));
        return s;
    }
    std::string sawLine(const std::string& text) const { return "grep -q '" + text + "' " + (dir_ / "err").string(); }
};

}  // namespace

// ---- 1. A received report is untrusted input ----

TEST_F(Edges, AReportsFlagsCannotWriteAnywhereOrStartAProgram) {
    const json base = baseReport();
    write(dir_ / "victim.png", "precious");
    const std::pair<std::string, std::string> hostile[] = {
        {"image=\"" + p("victim.png") + "\"", "'image'"},
        {"report=\"../elsewhere.json\"", "'report'"},
        {"vcd=\"" + p("w.vcd") + "\"", "'vcd'"},
        {"map=\"" + p("m.png") + "\"", "'map'"},
        {"as-baseline=true", "'as-baseline'"},
    };
    for (const auto& [line, mention] : hostile) {
        json r = base;
        r["rerun"]["flags"] = r["rerun"]["flags"].get<std::string>() + line + "\n";
        write(dir_ / "h.json", r.dump());
        bad("--rerun " + p("h.json") + " -q --image ''", mention);
    }
    EXPECT_EQ(slurp(dir_ / "victim.png"), "precious");
    for (const char* made : {"w.vcd", "m.png", "elsewhere.json"}) EXPECT_FALSE(fs::exists(dir_ / made)) << made;
    EXPECT_FALSE(fs::exists(dir_.parent_path() / "elsewhere.json"));
    EXPECT_TRUE(leftBehind().empty());
}

// A report from a build before a setting existed lacks it: the plain
// rerun is refused, naming the setting and the flag that reruns it with
// this build's value; with that flag the rerun is a what-if and runs, to
// the same image (the setting's default is the older build's behaviour).
// A setting with no flag of its own gets no hint.
TEST_F(Edges, ARerunOfAnOlderReportNamesTheFlagOfTheSettingItLacks) {
    json old = baseReport();
    old["config"].erase("primary_order");
    write(dir_ / "old.json", old.dump());
    bad("--rerun " + p("old.json") + " -q --image ''",
        "/primary_order: not in the report, \"scan\" here; a setting newer than the report's build: to rerun it as this "
        "build does, give it after the report (--rerun " + p("old.json") + " --primary-order scan)");
    const Outcome o = rtsim("--rerun " + p("old.json") + " --primary-order scan -q --image " + p("again.png"));
    EXPECT_EQ(o.code, 0) << o.err;
    const Outcome first = rtsim(std::string(kSmall) + " --no-baseline -q --image " + p("first.png"));
    EXPECT_EQ(first.code, 0) << first.err;
    EXPECT_EQ(slurp(dir_ / "again.png"), slurp(dir_ / "first.png"));
    json t = old;
    t["config"]["link"].erase("latency_ns");
    write(dir_ / "t.json", t.dump());
    bad("--rerun " + p("t.json") + " -q --image ''", "(--rerun " + p("t.json") + " --link-latency 100.0ns)");
    json c = baseReport();
    c["config"]["camera"].erase("fov_deg");
    write(dir_ / "c.json", c.dump());
    const Outcome noHint = rtsim("--rerun " + p("c.json") + " -q --image ''");
    EXPECT_EQ(noHint.code, 2);
    EXPECT_NE(noHint.err.find("/camera/fov_deg: not in the report, 40.0 here"), std::string::npos) << noHint.err;
    EXPECT_EQ(noHint.err.find("newer than"), std::string::npos) << noHint.err;
    // A setting the report holds with another value than this build's
    // default (a default changed since: --sample-links on came in so) names
    // the report's value, which reruns it as it ran.
    json d = baseReport();
    d["config"]["primary_order"] = "spread";
    write(dir_ / "d.json", d.dump());
    bad("--rerun " + p("d.json") + " -q --image ''",
        "/primary_order: \"spread\" there, \"scan\" here; the report's build ran it otherwise (a default changed since, or "
        "the report was edited): to rerun it as it ran, give the report's value after it (--rerun " + p("d.json") +
        " --primary-order spread)");
}

TEST_F(Edges, ARerunLoadsOnlyTheSceneItsReportRecords) {
    const json base = baseReport();  // procedural: 200 spheres
    // A report edited to another mesh than its flags give is refused, with
    // --no-baseline too: it changes no frame, so it is no what-if (with it
    // the edited report ran unchecked, 2x2x2).
    {
        json m = base;
        m["config"]["mesh"] = {3, 3, 3};
        write(dir_ / "m.json", m.dump());
        bad("--rerun " + p("m.json") + " -q --image ''", "arrives at other settings than the report's: /mesh/0: 3 there, 2 here");
        bad("--rerun " + p("m.json") + " --no-baseline -q --image ''", "/mesh/0: 3 there, 2 here");
    }
    // Flags naming a scene file that config.scene does not: refused before
    // the file is read (nothing of it echoed).
    json r = base;
    r["rerun"]["flags"] = r["rerun"]["flags"].get<std::string>() + "scene=\"" + scene("balls-1") + "\"\n";
    write(dir_ / "h.json", r.dump());
    bad("--rerun " + p("h.json") + " -q --image ''", "config.scene names none");
    // config.scene removed: no longer a report.
    r = base;
    r["config"].erase("scene");
    r["rerun"]["flags"] = r["rerun"]["flags"].get<std::string>() + "scene=\"/etc/passwd\"\n";
    write(dir_ / "h.json", r.dump());
    bad("--rerun " + p("h.json") + " -q --image ''", "config.scene: missing");
    // Another procedural scene in a what-if: refused; the command line's own choice is not.
    r = base;
    r["rerun"]["flags"] = r["rerun"]["flags"].get<std::string>() + "spheres=5000\n";
    write(dir_ / "h.json", r.dump());
    bad("--rerun " + p("h.json") + " --mesh 1 -q --image ''", "its flags give another scene than its config.scene records");
    EXPECT_EQ(rtsim("--rerun " + p("h.json") + " --spheres 300 -q --image ''").code, 0);
    // A scene file edited since.
    fs::copy_file(scene("balls-1"), dir_ / "s.nff");
    ASSERT_EQ(rtsim("--scene " + p("s.nff") + " --size 8x8 --mesh 1 --no-baseline -q --image '' --report " + p("f.json")).code, 0);
    std::ofstream(dir_ / "s.nff", std::ios::app) << "s 0 0 0 0.1\n";
    bad("--rerun " + p("f.json") + " --mesh 2 -q --image ''", "has changed since the report was written");
}

TEST_F(Edges, AMalformedReportIsOneLineNamingTheField) {
    const json base = baseReport();
    auto with = [&](auto change, const std::string& mention) {
        json r = base;
        change(r);
        write(dir_ / "h.json", r.dump());
        bad("--rerun " + p("h.json") + " -q --image ''", mention);
    };
    with([](json& r) { r["rerun"]["flags"] = 5; }, "rerun.flags: expected a string, got an integer");
    with([](json& r) { r["config"]["scene"] = "x"; }, "config.scene: expected an object, got a string");
    with([](json& r) { r["rerun"]["flags"] = "mesh = [2\n"; }, "rerun.flags:1: expected ',' or ']'");
    with([](json& r) { r["rerun"]["flags"] = "mesh = 99\n"; }, "rerun.flags:1: mesh = 99: --mesh");
    // Longer than a config file may be: a million lines, each checked alone, looked like a hang.
    with([](json& r) { r["rerun"]["flags"] = std::string(1100000, '#'); }, "rerun.flags: larger than 1048576 bytes");
    // Nested 300,000 deep (it crashed the comparison, SIGSEGV): refused as it is read.
    std::string deep = base.dump();
    deep.insert(deep.find("\"config\":{") + 10, "\"deep\":" + std::string(300000, '[') + std::string(300000, ']') + ",");
    write(dir_ / "deep.json", deep);
    bad("--rerun " + p("deep.json") + " -q --image ''", "nested more than 64 deep");
    // --boundaries-from takes a report too, read alike.
    bad(std::string(kSmall) + " --balance slide --boundaries-from " + p("deep.json") + " -q --image ''",
        "--boundaries-from " + p("deep.json") + ": nested more than 64 deep");
    // A boundary given twice: the later entry won, silently.
    json twice = base;
    ASSERT_FALSE(twice["boundaries"].empty());
    twice["boundaries"].push_back(twice["boundaries"][0]);
    write(dir_ / "twice.json", twice.dump());
    bad(std::string(kSmall) + " --balance slide --boundaries-from " + p("twice.json") + " -q --image ''", "boundaries: column 0,0's boundary 1 given twice");
    EXPECT_TRUE(leftBehind().empty());
}

TEST_F(Edges, ARerunOfARerunRecordsOnlyWhatItReran) {
    baseReport();
    std::string from = p("base.json");
    for (int i = 0; i < 3; ++i) {  // (each used to nest the one before: depth grew with every rerun)
        const std::string to = p("again" + std::to_string(i) + ".json");
        ASSERT_EQ(rtsim("--rerun " + from + " -q --image '' --report " + to).code, 0);
        from = to;
    }
    const json r = json::parse(slurp(from));
    EXPECT_TRUE(r["rerun"]["of"].contains("flags"));
    EXPECT_FALSE(r["rerun"]["of"].contains("of"));
}

// ---- 2. Outputs never destroy what the run did not create ----

TEST_F(Edges, AnOutputThatIsNotAFileOfItsOwnIsRefusedBeforeTheRun) {
    ASSERT_EQ(::mkfifo(p("fifo.vcd").c_str(), 0600), 0);
    bad(std::string(kSmall) + " --vcd " + p("fifo.vcd"), "--vcd: " + p("fifo.vcd") + ": is not a regular file");  // (it hung, opening it)
    EXPECT_TRUE(fs::is_fifo(p("fifo.vcd")));
    bad(std::string(kSmall) + " --report /dev/null", "--report: /dev/null: is not a regular file");
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    write(dir_ / "target.json", "mine");
    fs::create_symlink(p("target.json"), p("link.json"));
    bad(std::string(kSmall) + " --report " + p("link.json"), "is a symbolic link");
    EXPECT_EQ(slurp(dir_ / "target.json"), "mine");
    EXPECT_TRUE(fs::is_symlink(p("link.json")));
    // A name whose format is not the one written, --map's too, before the run.
    bad(std::string(kSmall) + " --map " + p("m.xyz") + " --report " + p("r.json"), "--map: " + p("m.xyz") + ": the name must end in .png, .svg, .pdf");
    EXPECT_FALSE(fs::exists(dir_ / "r.json"));
    bad(std::string(kSmall) + " --image " + p("x.jpg"), "must end in .png");
    EXPECT_TRUE(leftBehind().empty());
}

TEST_F(Edges, NoTwoOutputsAndNoOutputAndInputNameOneFile) {
    fs::copy_file(scene("balls-1"), dir_ / "scene.json");  // (an NFF scene, whatever its name)
    write(dir_ / "c.json", "mesh = 2\n");
    const json base = baseReport();
    const std::pair<std::string, std::string> clashes[] = {
        {" --image " + p("x.png") + " --map " + p("x.png"), "--map: " + p("x.png") + ": the same file as --image"},
        {" --vcd " + p("w.vcd") + " --map " + p("w.gtkw.png") + " --image " + p("./w.gtkw.png"), "the same file as --image"},
        // One file not there yet, named relative and otherwise (the run is in dir_): the map was written over the image.
        {" --image c1.png --map ./c1.png", "--map: ./c1.png: the same file as --image c1.png"},
        {" --image c2.png --map " + p("c2.png"), "the same file as --image c2.png"},
        {" --scene " + p("scene.json") + " --size 8x8 --report " + p("scene.json"), "the same file as the input --scene"},
        {" --config " + p("c.json") + " --report " + p("c.json"), "the same file as the input --config"},
        {" --boundaries-from " + p("base.json") + " --report " + p("base.json"), "the same file as the input --boundaries-from"},
        {" --rerun " + p("base.json") + " --report " + p("base.json"), "the same file as the input --rerun"},
    };
    for (const auto& [args, mention] : clashes) bad(std::string(args.find("--rerun") != std::string::npos ? "" : kSmall) + args, mention);
    EXPECT_EQ(json::parse(slurp(dir_ / "base.json")), base);
    EXPECT_EQ(slurp(dir_ / "c.json"), "mesh = 2\n");
    for (const char* f : {"c1.png", "c2.png"}) EXPECT_FALSE(fs::exists(dir_ / f)) << f;
}

TEST_F(Edges, AFailedRunLeavesEveryFileAsItWasAndNoTemporary) {
    for (const char* f : {"w.vcd", "w.gtkw", "r.json", "i.png"}) write(dir_ / f, std::string("old ") + f);
    // 1,000 s a sphere test: past 2^62 ps at a node (exit 1, in the run).
    const Outcome o = rtsim(" --size 64x64 --mesh 2 --cost-sphere 1000s --no-baseline -q --vcd " + p("w.vcd") + " --report " +
                            p("r.json") + " --image " + p("i.png"));
    EXPECT_EQ(o.code, 1) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
    for (const char* f : {"w.vcd", "w.gtkw", "r.json", "i.png"}) EXPECT_EQ(slurp(dir_ / f), std::string("old ") + f) << f;
    EXPECT_TRUE(leftBehind().empty());
}

// ---- 3. Derived times are checked against the picosecond range ----

TEST_F(Edges, ADerivedTimePastTheCounterIsRefusedNamingItsFlags) {
    // Each gave a normal-looking render time with exit 0 (the counter wrapped).
    bad(std::string(kSmall) + " --link-bandwidth 1e-6B/s", "--link-bandwidth with --ray-batch: a full ray message (132 bytes)");
    bad(std::string(kSmall) + " --link-set 1,0,0,-x:bandwidth=1e-9B/s", "--link-set 1,0,0,-x: a full ray message");
    bad(std::string(kSmall) + " --cost-host 1000s --fb-batch 65536", "--cost-host with --fb-batch");
    bad(std::string(kSmall) + " --speed 1e-15", "--speed 1e-15 with --cost-sphere");
    bad(std::string(kSmall) + " --node-speed 1,1,1=1e-15", "--node-speed 1,1,1=1e-15 with --cost-sphere");
    bad(std::string(kSmall) + " --balance slide --cost-rebuild 1000s", "--cost-rebuild: a slide's grid update for all 200 objects");
    bad(std::string(kSmall) + " --balance slide --link-bandwidth 10B/s --link-control-depth 2 --report-share 1e-6",
        "--link-bandwidth with --report-share");
    // sample's sum climbs each column in one message of up to kSampleValues
    // values (it stopped the run, exit 1, naming a link).
    bad(std::string(kSmall) + " --balance sample --link-bandwidth 1B/s",
        "--link-bandwidth with --balance sample: a sample's sum (1072 bytes) at 1 B/s");
    bad(std::string(kSmall) + " --balance recommended --link-set 1,0,0,-x:bandwidth=1B/s", "--link-set 1,0,0,-x: a sample's sum");
}

TEST_F(Edges, ABacklogPastTheCounterStopsTheRunNamingTheLink) {
    // Each ray message 132 s on the wire, a million of them queued.
    const Outcome o = rtsim(" --size 1024x1024 --mesh 2 --link-bandwidth 1B/s --no-baseline -q --image ''");
    EXPECT_EQ(o.code, 1) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
    EXPECT_NE(o.err.find("_p"), std::string::npos) << o.err;  // a link: node_X_Y_Z_px ...
    EXPECT_NE(o.err.find("the picosecond counter would wrap"), std::string::npos) << o.err;
}

// ---- 4. Stops that stop; memory bounded ----

TEST_F(EdgesTimed, ASignalInStartUpEndsRtsimAtOnceLeavingNothing) {
    // 300,000 spheres: binning them into 64 grids takes seconds; the signal
    // comes once the estimate is out (-v), while the grids are built.
    const Stopped s = stopWhen("--spheres 300000 --size 8x8 --no-baseline -q -v --vcd " + p("w.vcd") + " --report " + p("r.json"),
                               sawLine("grids at the frame"), "TERM");
    EXPECT_EQ(s.code, 143) << s.err;
    EXPECT_LT(s.ms, 1000);
    EXPECT_NE(s.err.find("rtsim: stopped by signal 15 (SIGTERM) during start-up"), std::string::npos) << s.err;
    EXPECT_FALSE(fs::exists(dir_ / "w.vcd"));
    EXPECT_FALSE(fs::exists(dir_ / "r.json"));
    EXPECT_TRUE(leftBehind().empty());
    // The wall-clock limit there too: exit 3.
    const Outcome w = rtsim("--spheres 300000 --size 8x8 --no-baseline -q --watchdog-wall 0.3");
    EXPECT_EQ(w.code, 3) << w.err;
    EXPECT_NE(w.err.find("the wall-clock limit of 0.3 s was reached during start-up"), std::string::npos) << w.err;
}

TEST_F(EdgesTimed, ASignalBetweenFramesStopsTheSequenceWithItsFramesSoFar) {
    // 10,000 frames (about 5 s, at 0.5 ms a frame): a signal at the second second.
    const Stopped s = stopWhen(std::string(kSmall) + " --frames 10000 --balance slide --no-baseline -q --image '' --report " + p("r.json"),
                               "sleep 1", "TERM");
    EXPECT_EQ(s.code, 143) << s.err;
    EXPECT_LT(s.ms, 1000);
    const json r = json::parse(slurp(dir_ / "r.json"));
    ASSERT_TRUE(r.contains("incomplete"));
    EXPECT_NE(r["incomplete"].get<std::string>().find(" of 10000: "), std::string::npos) << r["incomplete"];
    EXPECT_LT(r["frames"].size(), 10000u);
    EXPECT_GT(r["frames"].size(), 1u);
    EXPECT_TRUE(leftBehind().empty());
    // The wall-clock limit: the whole sequence's, not each frame's.
    const Outcome w = rtsim(std::string(kSmall) + " --frames 10000 --balance slide --no-baseline -q --image '' --watchdog-wall 1 --report " + p("w.json"));
    EXPECT_EQ(w.code, 3) << w.err;
    EXPECT_LT(json::parse(slurp(dir_ / "w.json"))["frames"].size(), 10000u);
}

TEST_F(EdgesTimed, ASignalInTheReferenceRunsWritesTheFinishedFrame) {
    // The 1x1x1 baseline of a 256x256 frame runs for seconds after the frame.
    const Stopped s = stopWhen(" --spheres 2000 --size 256x256 --mesh 4 -v --report " + p("r.json") + " --image " + p("i.png"),
                               sawLine("reference runs:"), "TERM");
    EXPECT_EQ(s.code, 143) << s.err;
    EXPECT_LT(s.ms, 1000);
    const json r = json::parse(slurp(dir_ / "r.json"));
    EXPECT_FALSE(r.contains("incomplete"));  // the frame itself is done
    EXPECT_NE(r.value("reference_runs_stopped", "").find("(a signal)"), std::string::npos) << r.dump().substr(0, 300);
    EXPECT_TRUE(fs::exists(dir_ / "i.png"));
    EXPECT_TRUE(leftBehind().empty());
}

TEST_F(EdgesTimed, ATemporaryASigkillLeftIsRemovedByTheNextRun) {
    // SIGKILL cannot be caught: the children's reports stay in TMPDIR...
    const Stopped s = stopWhen(" --spheres 2000 --size 256x256 --mesh 4 -v --image ''", sawLine("reference runs:"), "KILL");
    EXPECT_EQ(s.code, 137) << s.err;
    auto names = [&] {
        std::vector<std::string> out;
        for (const auto& e : fs::directory_iterator(tmp())) out.push_back(e.path().filename().string());
        return out;
    };
    const std::vector<std::string> left = names();
    ASSERT_FALSE(left.empty());
    for (const std::string& n : left) EXPECT_EQ(n.rfind("rtsim-child-", 0), 0u) << n;
    // ...until the next run with a child of its own removes them; one of a
    // process still running stays.
    const std::string running = "rtsim-child-" + std::to_string(getpid()) + "-abcdef.json";
    write(tmp() / running, "{}");
    const Outcome o = rtsim(std::string(kSmall) + " --mesh 2 -q --image ''");
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_EQ(names(), std::vector<std::string>{running});
}

TEST_F(Edges, AFrameSequenceKeepsOneReportNotOnePerFrame) {
    // Peak memory of rtsim itself (not its children) for 2 and for 24 frames
    // of a 512-node mesh, whose report is several MB.
    auto peakKb = [&](int frames) {
        const std::string cmd = std::string(RTSIM_EXE) + " --spheres 500 --size 16x16 --mesh 8 --balance slide --frames " +
                                std::to_string(frames) + " --no-baseline -q --image ''";
        const pid_t pid = fork();
        if (pid == 0) {
            // (Under AddressSanitizer freed memory waits in a quarantine of
            // 256 MB, which would measure ASan, not rtsim: none here.)
            execl("/bin/sh", "sh", "-c", ("ASAN_OPTIONS=\"$ASAN_OPTIONS:quarantine_size_mb=0\" exec " + cmd).c_str(),
                  (char*)nullptr);
            _exit(127);
        }
        int status = 0;
        rusage u{};
        wait4(pid, &status, 0, &u);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
        return long(u.ru_maxrss);
    };
    const long two = peakKb(2), many = peakKb(24);
    EXPECT_LT(many, two + 60 * 1024) << two << " KB for 2 frames, " << many << " KB for 24";
}

TEST_F(Edges, ASceneTooBigToBinIsRefusedWithAnEstimate) {
    // 40,000 spheres that all overlap: every grid lists every sphere in
    // every cell (billions of references at N = 4).
    std::ostringstream nff;
    nff << "v\nfrom 0 0 -3\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\nl 0 10 -10\nf 1 0 0 0.5 0.5 0 0 1\n";
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 40000; ++i) nff << "s " << u(rng) << " " << u(rng) << " " << u(rng) << " 2\n";
    write(dir_ / "overlap.nff", nff.str());
    bad("--scene " + p("overlap.nff") + " --mesh 4 --no-baseline -q --image ''", "objects binned into the 64 nodes' grids");
    const Outcome ref = run(std::string("timeout 60 ") + RTREF_EXE + " " + p("overlap.nff") + " -o " + p("o.png"));
    EXPECT_EQ(ref.code, 2) << ref.err;
    EXPECT_NE(ref.err.find("references (objects listed in cells), more than a grid holds"), std::string::npos) << ref.err;
}

TEST_F(Edges, AJobPastTheProcesssAddressSpaceLimitIsRefusedBeforeItStarts) {
    if (std::getenv("ASAN_OPTIONS")) GTEST_SKIP() << "AddressSanitizer's shadow memory needs more address space";
    // About 14 GiB in one process (a 32x32x32 mesh, an 11500x11500 image),
    // under `ulimit -v 8000000` (7.6 GiB) on a machine with more: it started
    // and ended in std::bad_alloc.
    const std::string job = std::string(RTSIM_EXE) + " --mesh 32 --spheres 1 --size 11500x11500 --no-baseline -q --image ''";
    const Outcome o = run("bash -c \"ulimit -v 8000000 && TMPDIR=" + tmp().string() + " exec timeout 60 " + job + "\"", dir_);
    EXPECT_EQ(o.code, 2) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
    EXPECT_NE(o.err.find("address-space limit (RLIMIT_AS, ulimit -v) is 7.6 GiB"), std::string::npos) << o.err;
}

// ---- 4b. The wall clock: the whole run and its parts ----

TEST_F(Edges, TheWallClockIsTheWholeRunItsPartsAddUpAndTheReferenceRunsAreOne) {
    // The whole: within this of the time measured outside rtsim (which adds
    // the exec, the dynamic loader, the summary and the exit), and each
    // printed part rounded to 1 ms. Under AddressSanitizer a process's start
    // and exit take longer: `rtsim --help` took 0.20 s there on the 2-core
    // machine, and this run 0.18 s outside its own wall clock.
#if defined(__SANITIZE_ADDRESS__)
    constexpr double kOutside = 0.5, kRounding = 0.0025;
#else
    constexpr double kOutside = 0.15, kRounding = 0.0025;
#endif
    // Outside time on a loaded machine (the suite's other tests) can exceed
    // the run's by more than kOutside: the closest of three runs is judged.
    for (const bool baseline : {true, false}) {
        SCOPED_TRACE(baseline ? "with its reference runs" : "--no-baseline");
        Outcome o{};
        json w;  // the judged run's report's wall_clock
        double outside = 0;
        for (int attempt = 0; attempt < 3; ++attempt) {
            const auto t0 = std::chrono::steady_clock::now();
            o = rtsim(std::string(kSmall) + " --frames 2 --balance measured --image '' --report " + p("w.json") +
                      (baseline ? "" : " --no-baseline"));
            outside = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (o.code != 0) break;
            w = json::parse(slurp(dir_ / "w.json"))["wall_clock"];
            if (w["total_s"].get<double>() + kOutside >= outside) break;
        }
        ASSERT_EQ(o.code, 0) << o.err;
        const double parts = w["start_up_s"].get<double>() + w["frames_s"].get<double>() +
                             w["reference_runs_s"].get<double>() + w["writing_s"].get<double>();
        EXPECT_NEAR(parts, w["total_s"].get<double>(), 1e-9);
        EXPECT_EQ(w["reference_runs_s"].get<double>() > 0, baseline) << w;
        const std::regex line(R"(wall clock +([0-9.]+) s in all: start-up ([0-9.]+) s, frames \(2\) ([0-9.]+) s, )"
                              R"(reference runs ([0-9.]+) s[^,]*, writing ([0-9.]+) s)");
        std::smatch m;
        ASSERT_TRUE(std::regex_search(o.out, m, line)) << o.out;
        double printed[5];
        for (int i = 0; i < 5; ++i) printed[i] = std::stod(m[i + 1]);
        EXPECT_NEAR(printed[1] + printed[2] + printed[3] + printed[4], printed[0], 4 * kRounding);
        EXPECT_LE(printed[0], outside + kRounding);
        EXPECT_GE(printed[0], outside - kOutside) << "the summary's whole leaves out part of the run";
        EXPECT_GE(printed[0], w["total_s"].get<double>() - kRounding);  // (the summary's also has the report's writing)
        EXPECT_EQ(printed[3] > 0, baseline);
    }
}

// ---- 4c. The report's detail: practical at any mesh ----

TEST_F(Edges, ASummaryReportKeepsWhatIsReadAndAutoChoosesItForABigMesh) {
    const std::string run = std::string(kSmall) + " --balance measured --frames 2 --no-baseline -q --image ''";
    ASSERT_EQ(rtsim(run + " --report " + p("full.json")).code, 0);
    const Outcome o = rtsim(run + " --report-detail summary --report " + p("sum.json"));
    ASSERT_EQ(o.code, 0) << o.err;
    const std::string fullText = slurp(dir_ / "full.json"), sumText = slurp(dir_ / "sum.json");
    EXPECT_LT(sumText.size() * 2, fullText.size());
    json full = json::parse(fullText), sum = json::parse(sumText);
    EXPECT_EQ(full["report_detail"]["level"], "full");
    EXPECT_EQ(sum["report_detail"], json({{"level", "summary"}, {"why", "--report-detail summary"}}));
    // What the summary, the mesh map, --trace-nodes busiest, the frame loop and scripts read: the same.
    for (const char* k : {"render_time_ns", "busiest_links", "boundaries", "totals", "bounds", "balance", "config", "frames"})
        EXPECT_EQ(sum[k], full[k]) << k;
    ASSERT_EQ(sum["nodes"].size(), full["nodes"].size());
    for (size_t i = 0; i < sum["nodes"].size(); ++i)
        for (const char* k : {"node", "box", "busy_ns", "wait_ns", "load", "busy_by_category", "rays_traced", "counters",
                              "grid", "work_by_position"})
            ASSERT_EQ(sum["nodes"][i][k], full["nodes"][i][k]) << k;
    ASSERT_EQ(sum["links"].size(), full["links"].size());
    for (size_t i = 0; i < sum["links"].size(); ++i)
        for (const char* k : {"name", "from", "to", "utilisation", "saturated_ns", "peak_utilisation"})
            ASSERT_EQ(sum["links"][i][k], full["links"][i][k]) << k;
    EXPECT_FALSE(sum["links"][0].contains("messages"));  // (left out)
    // A summary runs again, and continues a sequence as the full report does.
    const Outcome again = rtsim("--rerun " + p("sum.json") + " -q --image '' --report " + p("again.json"));
    ASSERT_EQ(again.code, 0) << again.err;
    EXPECT_EQ(json::parse(slurp(dir_ / "again.json"))["render_time_ns"], sum["render_time_ns"]);
    const std::string next = std::string(kSmall) + " --balance measured --no-baseline -q --image '' --boundaries-from ";
    ASSERT_EQ(rtsim(next + p("full.json") + " --report " + p("n1.json")).code, 0);
    ASSERT_EQ(rtsim(next + p("sum.json") + " --report " + p("n2.json")).code, 0);
    EXPECT_EQ(json::parse(slurp(dir_ / "n1.json"))["boundaries"], json::parse(slurp(dir_ / "n2.json"))["boundaries"]);
    // auto: full up to 4096 nodes, a summary beyond, and the report says why.
    ASSERT_EQ(rtsim("--mesh-dims 17x16x16 --spheres 1 --size 8x8 --no-baseline -q --image '' --report " + p("big.json")).code, 0);
    EXPECT_EQ(json::parse(slurp(dir_ / "big.json"))["report_detail"],
              json({{"level", "summary"}, {"why", "--report-detail auto: 4352 nodes, more than 4096"}}));
    bad(run + " --report-detail some", "--report-detail");
}

// ---- 5. Config files: the last value wins, each value checked ----

TEST_F(Edges, ConfigFilesAreReadWholeInOrderAndTheLastValueWins) {
    write(dir_ / "a.conf", "mesh = 3\nspheres = 200\nsize = 16x16\nmesh = 2  # adjacent or not, the last one\n");
    write(dir_ / "b.conf", "link-latency = 250ns\nfb-units = 3\n");
    const Outcome o = rtsim("--config " + p("a.conf") + " --config " + p("b.conf") + " --fb-units 2 -q --no-baseline --image '' --report " + p("r.json"));
    ASSERT_EQ(o.code, 0) << o.err;
    const json r = json::parse(slurp(dir_ / "r.json"));
    EXPECT_EQ(r["config"]["mesh"], json({2, 2, 2}));                       // a.conf's last line
    EXPECT_EQ(r["config"]["link"]["latency_ns"].get<double>(), 250.0);     // b.conf was read too
    EXPECT_EQ(r["config"]["fb_units"].get<int>(), 2);                     // the command line last
    write(dir_ / "c.conf", "mesh = 2\nmesh = abc\n");
    bad("--config " + p("c.conf"), p("c.conf") + ":2: mesh = abc: --mesh");  // it was silently ignored
    write(dir_ / "d.conf", "mesh = 2\nnode-speed = 5,5,5=2\n");
    bad("--config " + p("d.conf") + " -q --no-baseline --image ''", p("d.conf") + ":2: --node-speed: node outside the mesh");
}
