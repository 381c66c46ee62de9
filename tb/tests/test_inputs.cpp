// rtsim's edges, part by part (doc/robustness.md, "Edges"): the config
// reader, the JSON reader, the merge of files, reports and command line,
// the output policy, and the derived times. End to end, as a user meets
// them: test_edges.cpp.
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "cli_test.h"
#include "command_line.h"
#include "config_file.h"
#include "node/cost_model.h"
#include "grid.h"
#include "job_memory.h"
#include "json_input.h"
#include "config/machine_config.h"
#include "memory_estimate.h"
#include "output_file.h"
#include "scene_error.h"
#include "rtsim_cli.h"
#include "sphere.h"
#include "subprocess.h"
#include "base/units.h"
#include "process/watchdog.h"
#include "trace/vcd_stream.h"

using namespace rt;
using rt::test::parsed;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The message of what `f` throws as E; fails the test if it throws nothing.
template <class E, class F>
std::string thrown(F&& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    ADD_FAILURE() << "nothing thrown";
    return "";
}

// A fresh folder per test.
class Folder : public testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("rt_inputs_" + std::to_string(::getpid()) + "_" +
                                            testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }
    std::string read(const std::string& name) const {
        std::ifstream in(dir_ / name);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }
    std::vector<std::string> left() const {  // temporaries left in the folder
        std::vector<std::string> out;
        for (const auto& e : fs::directory_iterator(dir_))
            if (e.path().string().find(".incomplete-") != std::string::npos) out.push_back(e.path().string());
        return out;
    }
    fs::path dir_;
};

}  // namespace

// ---- The config reader (config_file.h) ----

TEST(ConfigFile, ReadsEachFormOfAValue) {
    const auto lines = parseConfig(
        "# a comment\n; another\n\nmesh = 4\nlink-latency = 100ns   # why\nscene = \"/data/my #1 scene.nff\"\n"
        "image = 'C:\\raw'\nlight = [1, 2, 3, 4, 5, 6]\nno-baseline\nsize=16x16\nname = a b c\nq = \"tab\\there\"\n",
        "c.conf");
    ASSERT_EQ(lines.size(), 9u);
    EXPECT_EQ(lines[0].name, "mesh");
    EXPECT_EQ(lines[0].values, std::vector<std::string>{"4"});
    EXPECT_EQ(lines[0].where, "c.conf:4");
    EXPECT_EQ(lines[1].values, std::vector<std::string>{"100ns"});       // the comment cut
    EXPECT_EQ(lines[2].values, std::vector<std::string>{"/data/my #1 scene.nff"});  // a '#' inside quotes kept
    EXPECT_EQ(lines[3].values, std::vector<std::string>{"C:\\raw"});    // no escapes in '...'
    EXPECT_EQ(lines[4].values, (std::vector<std::string>{"1", "2", "3", "4", "5", "6"}));
    EXPECT_TRUE(lines[4].list);
    EXPECT_EQ(lines[5].values, std::vector<std::string>{"true"});  // a flag alone
    EXPECT_EQ(lines[6].values, std::vector<std::string>{"16x16"});
    EXPECT_EQ(lines[7].values, std::vector<std::string>{"a b c"});  // a bare value keeps its spaces
    EXPECT_EQ(lines[8].values, std::vector<std::string>{"tab\there"});
    EXPECT_EQ(lines[8].where, "c.conf:12");
    // A UTF-8 byte-order mark before the first line (it was "expected a flag's name").
    const auto bom = parseConfig("\xEF\xBB\xBFmesh = 2\n", "b.conf");
    ASSERT_EQ(bom.size(), 1u);
    EXPECT_EQ(bom[0].name, "mesh");
    EXPECT_EQ(bom[0].where, "b.conf:1");
}

TEST(ConfigFile, EachBadLineNamesItsFileAndLine) {
    const std::pair<const char*, const char*> bad[] = {
        {"mesh = 2\n[section]\n", "c.conf:2: sections"},
        {"scene = \"open\n", "c.conf:1: a string not closed"},
        {"image = 'open\n", "c.conf:1: a string not closed"},
        {"light = [1, 2\n", "c.conf:1: expected ',' or ']'"},
        {"mesh =\n", "c.conf:1: no value"},
        {"mesh = 2\n= 3\n", "c.conf:2: expected a flag's name"},
        {"mesh \"2\"\n", "c.conf:1: expected '='"},
        {"scene = \"a\" b\n", "c.conf:1: more after the value"},
        {"scene = \"\\q\"\n", "c.conf:1: a string with an escape"},
    };
    for (const auto& [text, mention] : bad) {
        SCOPED_TRACE(text);
        EXPECT_NE(thrown<ConfigError>([&] { parseConfig(text, "c.conf"); }).find(mention), std::string::npos);
    }
    EXPECT_NE(thrown<ConfigError>([] { parseConfig(std::string("mesh = 2\0\n", 10), "c.conf"); }).find("c.conf:1: a NUL byte"),
              std::string::npos);
}

TEST(ConfigFile, WhatItWritesItReadsBack) {
    // Strings of every awkward kind: quotes, backslashes, '#', spaces, a
    // lone character, numbers, control characters.
    std::mt19937 rng(7);
    const std::string alphabet = "ab #\"'\\[],=;\t1.e-x/";
    for (int i = 0; i < 2000; ++i) {
        std::vector<std::string> values(1 + rng() % 3);
        for (auto& v : values) {
            const size_t n = rng() % 8;
            for (size_t k = 0; k < n; ++k) v += alphabet[rng() % alphabet.size()];
        }
        const std::string line = configLine("flag", values);
        SCOPED_TRACE(line);
        const auto back = parseConfig(line + "\n", "x");
        ASSERT_EQ(back.size(), 1u);
        EXPECT_EQ(back[0].values, values);
    }
}

// ---- The JSON reader (json_input.h) ----

TEST_F(Folder, JsonIsReadWithinLimitsAndEachFieldByItsPath) {
    write("deep.json", std::string(kMaxJsonDepth + 1, '[') + std::string(kMaxJsonDepth + 1, ']'));
    EXPECT_NE(thrown<JsonInputError>([&] { readJsonFile(path("deep.json"), 1 << 20); }).find("nested more than 64 deep"),
              std::string::npos);
    write("ok.json", std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']'));
    EXPECT_NO_THROW(readJsonFile(path("ok.json"), 1 << 20));
    write("bad.json", "{\"a\": [1, 2,}");
    EXPECT_NE(thrown<JsonInputError>([&] { readJsonFile(path("bad.json"), 1 << 20); }).find("not JSON (at byte 13)"), std::string::npos);
    // Valid syntax, but past a double (the parser throws out_of_range, not
    // parse_error; found by fuzz_report).
    EXPECT_EQ(thrown<JsonInputError>([&] { parseJsonText(R"({"a": 1.6E604127579737336})", "r.json"); }),
              "r.json: a number too large for a double (not a report)");
    EXPECT_NE(thrown<JsonInputError>([&] { readJsonFile(path("ok.json"), 10); }).find("larger than 10 bytes"), std::string::npos);
    EXPECT_NE(thrown<JsonInputError>([&] { readJsonFile("/dev/null", 10); }).find("not a regular file"), std::string::npos);
    const json r = json::parse(R"({"config": {"scene": {"file": 3}}, "rerun": {"flags": "mesh=2\n"}})");
    EXPECT_EQ(jsonField(r, "rerun.flags", json::value_t::string, "r.json").get<std::string>(), "mesh=2\n");
    EXPECT_EQ(thrown<JsonInputError>([&] { jsonField(r, "config.scene.file", json::value_t::string, "r.json"); }),
              "r.json: config.scene.file: expected a string, got an integer");
    EXPECT_EQ(thrown<JsonInputError>([&] { jsonField(r, "config.mesh", json::value_t::array, "r.json"); }),
              "r.json: config.mesh: missing");
}

// ---- The merge: files, reports, command line (command_line.h) ----

namespace {

CommandLine merge(const std::vector<std::pair<std::string, bool>>& texts, const std::vector<std::string>& rest) {
    std::vector<ConfigSource> sources;
    for (size_t i = 0; i < texts.size(); ++i)
        sources.push_back({parseConfig(texts[i].first, "f" + std::to_string(i + 1)), texts[i].second});
    return mergeFlags(sources, rest, "rtsim");
}

}  // namespace

TEST(CommandLine, TheLastValueWinsEverywhere) {
    // Within a file (adjacent or not), across files in order, then the command line.
    EXPECT_EQ(parsed(merge({{"mesh = 2\nmesh = 3\n", false}}, {})).mesh, 3);
    EXPECT_EQ(parsed(merge({{"mesh = 2\nfb-units = 3\nmesh = 3\n", false}}, {})).mesh, 3);
    EXPECT_EQ(parsed(merge({{"mesh = 2\n", false}, {"mesh = 3\n", false}}, {})).mesh, 3);
    EXPECT_EQ(parsed(merge({{"mesh = 2\n", false}, {"mesh = 3\n", false}}, {"--mesh", "1"})).mesh, 1);
    // A repeatable flag's lines in one file are its list (the first was dropped,
    // with no message), a non-repeatable one's the last; a later file replaces the list whole.
    const RtsimOptions lines = parsed(merge({{"mesh = 3\nnode-speed = \"0,0,0=2\"\nmesh = 2\nnode-speed = \"1,1,1=3\"\n"
                                              "eye = [0, -2, 0]\neye = [0, -3, 0]\n", false}}, {}));
    EXPECT_EQ(lines.machine.nodeSpeed.size(), 2u);
    EXPECT_EQ(lines.machine.nodeSpeed.count({0, 0, 0}), 1u);
    EXPECT_EQ(lines.machine.nodeSpeed.count({1, 1, 1}), 1u);
    EXPECT_EQ(lines.mesh, 2);
    // A repeatable flag's list is replaced whole by a later file, not added to.
    const RtsimOptions o = parsed(merge({{"mesh = 2\nnode-speed = [\"0,0,0=2\", \"1,1,1=3\"]\n", false},
                                         {"node-speed = \"1,0,0=5\"\n", false}},
                                        {}));
    EXPECT_EQ(o.machine.nodeSpeed.size(), 1u);
    EXPECT_EQ(o.machine.nodeSpeed.count({1, 0, 0}), 1u);
    const RtsimOptions c = parsed(merge({{"mesh = 2\nnode-speed = \"1,0,0=5\"\n", false}}, {"--node-speed", "0,1,0=2"}));
    EXPECT_EQ(c.machine.nodeSpeed.size(), 1u);
    EXPECT_EQ(c.machine.nodeSpeed.count({0, 1, 0}), 1u);
    // Where each value came from, for errors found after the merge.
    const CommandLine cl = merge({{"mesh = 2\n", false}, {"\nnode-speed = \"5,5,5=2\"\n", false}}, {});
    EXPECT_EQ(cl.originOf("--node-speed: node outside the mesh"), "f2:2: ");
    EXPECT_EQ(cl.originOf("--fb-units: x"), "");
}

// --mesh and --mesh-dims are one setting: a preset's mesh-dims beat --mesh on the
// command line (silently), and both on the command line ran --mesh-dims.
TEST(CommandLine, MeshAndMeshDimsAreOneSetting) {
    EXPECT_EQ(parsed(merge({{"mesh-dims = 1x2x3\n", false}}, {"--mesh", "2"})).machine.dims, (std::array<int, 3>{2, 2, 2}));
    EXPECT_EQ(parsed(merge({{"mesh = 3\n", false}}, {"--mesh-dims", "1x2x3"})).machine.dims, (std::array<int, 3>{1, 2, 3}));
    EXPECT_EQ(parsed(merge({{"mesh = 3\nmesh-dims = 1x2x3\n", false}}, {})).machine.dims, (std::array<int, 3>{1, 2, 3}));
    EXPECT_EQ(parsed(merge({{"mesh-dims = 1x2x3\n", false}, {"mesh = 3\n", false}}, {})).machine.dims,
              (std::array<int, 3>{3, 3, 3}));
    EXPECT_NE(thrown<ConfigError>([&] { merge({}, {"--mesh", "2", "--mesh-dims", "1x1x2"}); }).find("--mesh and --mesh-dims"),
              std::string::npos);
}

TEST(CommandLine, EachValueOfAFileIsCheckedAloneNamingItsLine) {
    const std::pair<std::string, std::string> bad[] = {
        {"mesh = 2\nmesh = abc\n", "f1:2: mesh = abc: --mesh"},   // was silently ignored
        {"no-such-flag = 3\n", "f1:1: no flag --no-such-flag"},
        {"--mesh = 2\n", "f1:1: '--mesh': write the flag's long name without its dashes: 'mesh = ...'"},  // said "no flag ----mesh"
        {"-mesh = 2\n", "f1:1: '-mesh': write the flag's long name without its dashes: 'mesh = ...'"},  // said "the short --mesh"
        {"-q = true\n", "f1:1: '-q': write the flag's long name without its dashes: 'quiet = ...'"},
        {"--nosuch = 3\n", "f1:1: '--nosuch': no flag of that name"},
        {"-5 = 3\n", "f1:1: '-5': no flag of that name"},
        {"config = other.conf\n", "f1:1: --config is read only from the command line"},
        {"mesh = [2, 3]\n", "f1:1: mesh takes one value, not a list of 2"},
        {"link-latency = 5\n", "f1:1: link-latency = 5: --link-latency"},
        {"quantum = soon\n", "f1:1: quantum = soon: --quantum"},
        {"mesh-dims = 2x2\n", "f1:1: mesh-dims = 2x2: --mesh-dims"},
        {"no-baseline = [true, false]\n", "f1:1: no-baseline is a flag"},
        // A name alone is a flag set; a setting that takes a value says so
        // (it said "sample-links = true: ... got 'true'", a value never written).
        {"sample-links\n", "f1:1: sample-links alone: it takes a value ('sample-links = ...')"},
        {"mesh\n", "f1:1: mesh alone: it takes a value"},
    };
    for (const auto& [text, mention] : bad) {
        SCOPED_TRACE(text);
        EXPECT_NE(thrown<ConfigError>([&] { merge({{text, false}}, {}); }).find(mention), std::string::npos);
    }
    EXPECT_NO_THROW(merge({{"no-guard\n", false}}, {}));  // (a flag alone is the flag set)
}

TEST(CommandLine, AReportsFlagsNeverNameAnOutputOrAnInternalFlag) {
    for (const char* line : {"image = \"/tmp/x.png\"", "report = \"../elsewhere.json\"", "vcd = \"w.vcd\"", "map = \"m.png\"",
                             "quiet = true", "verbose = 2", "config = \"c.conf\"", "rerun = \"r.json\"",
                             "as-baseline = true", "as-comparison = true"}) {
        SCOPED_TRACE(line);
        const std::string e = thrown<ConfigError>([&] { merge({{std::string("mesh = 2\n") + line + "\n", true}}, {}); });
        EXPECT_NE(e.find("f1:2: '"), std::string::npos) << e;
        EXPECT_NE(e.find("never name an output"), std::string::npos) << e;
    }
    // From the command line they are the user's own.
    EXPECT_EQ(parsed(merge({{"mesh = 2\n", true}}, {"--image", "mine.png"})).image, "mine.png");
}

// ---- The output policy (sw/output_file.h) ----

TEST_F(Folder, AnOutputIsAbsentOrARegularFileOfItsOwn) {
    EXPECT_NO_THROW(checkWritable("--report", path("new.json")));
    write("old.json", "{}");
    EXPECT_NO_THROW(checkWritable("--report", path("old.json")));
    ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
    fs::create_symlink(path("old.json"), path("link.json"));
    const std::pair<std::string, std::string> bad[] = {
        {path("fifo"), "is not a regular file"},
        {"/dev/null", "is not a regular file"},
        {path("link.json"), "is a symbolic link"},
        {dir_.string(), "is a folder"},
        {path("no/such/x.json"), "no such folder"},
        {"", "an empty name"},
    };
    for (const auto& [p, mention] : bad) {
        SCOPED_TRACE(p);
        EXPECT_NE(thrown<OutputError>([&] { checkWritable("--report", p); }).find(mention), std::string::npos);
    }
    EXPECT_TRUE(fs::is_fifo(path("fifo")));  // all still there
    EXPECT_EQ(fs::read_symlink(path("link.json")), path("old.json"));
    EXPECT_NO_THROW(checkExtension("--image", "A.PNG", {".png"}));
    EXPECT_NE(thrown<OutputError>([] { checkExtension("--map", "m.xyz", {".png", ".svg"}); }).find("must end in .png, .svg"),
              std::string::npos);
}

TEST_F(Folder, NoTwoOutputsAndNoOutputAndInputNameOneFile) {
    write("scene.nff", "s 0 0 0 1\n");
    fs::create_hard_link(path("scene.nff"), path("hard.json"));
    const std::pair<std::vector<NamedFile>, std::string> bad[] = {
        {{{"--image", path("x.png")}, {"--map", path("x.png")}}, "--map: " + path("x.png") + ": the same file as --image"},
        {{{"--image", path("x.png")}, {"--map", dir_.string() + "/./x.png"}}, "the same file as --image"},
        {{{"--scene", path("scene.nff"), false}, {"--report", path("hard.json")}}, "the same file as the input --scene"},
        {{{"--report", path("r.json")}, {"--boundaries-from", path("r.json"), false}}, "the same file as the input --boundaries-from"},
    };
    for (const auto& [files, mention] : bad) {
        SCOPED_TRACE(mention);
        EXPECT_NE(thrown<OutputError>([&] { checkDistinct(files); }).find(mention), std::string::npos);
    }
    EXPECT_NO_THROW(checkDistinct({{"--config", path("a"), false}, {"--scene", path("a"), false}, {"--image", path("b.png")}}));
}

TEST_F(Folder, AnOutputIsRenamedIntoPlaceOrLeavesNothing) {
    write("keep.json", "before");
    {
        AtomicFile f(path("keep.json"));
        EXPECT_EQ(fs::path(f.temp()).filename().string().rfind("keep.json.incomplete-", 0), 0u);  // a name that says so
        f.write("after");
    }  // not committed: the temporary goes, the file stays
    EXPECT_TRUE(left().empty());
    EXPECT_EQ(read("keep.json"), "before");
    AtomicFile g(path("keep.json"));
    g.write("after");
    g.commit();
    EXPECT_TRUE(left().empty());
    EXPECT_EQ(read("keep.json"), "after");
    // A signal that ends the process at once removes the temporaries held.
    AtomicFile h(path("third.json"));
    ASSERT_EQ(left().size(), 1u);
    removeTempFilesNow();
    EXPECT_TRUE(left().empty());
}

// A stop that comes while a temporary file is made and registered
// (StopsHeld: AtomicFile, checkWritable, TempFile) is handled when the
// scope ends, when the file is registered or gone: a SIGTERM to a
// reference run in its start-up, between the two, left one behind.
namespace {
volatile sig_atomic_t stopsSeen = 0;
void countStop(int) { stopsSeen = stopsSeen + 1; }
}  // namespace

TEST(OutputFile, AStopWhileATemporaryIsMadeWaitsForTheScopeToEnd) {
    struct sigaction count {}, before {};
    count.sa_handler = countStop;
    sigemptyset(&count.sa_mask);
    ASSERT_EQ(sigaction(SIGTERM, &count, &before), 0);
    stopsSeen = 0;
    {
        const StopsHeld held;
        raise(SIGTERM);
        EXPECT_EQ(stopsSeen, 0);  // held
    }
    EXPECT_EQ(stopsSeen, 1);  // handled as the scope ended
    sigaction(SIGTERM, &before, nullptr);
}

TEST(VcdStream, AWriteThatFailsIsAnErrorNamingTheVcd) {
    VcdStream v;
    const int s = v.declare("node_0_0_0", "busy", VcdStream::Kind::Bit);
    const std::string e = thrown<std::runtime_error>([&] {
        v.open("/dev/full", 0, ~Picos(0), "w.vcd");  // (a full disk)
        for (Picos t = 1; t < 400000; ++t) v.set(t, s, int64_t(t % 2));
        v.close(400000, "");
    });
    EXPECT_NE(e.find("w.vcd: cannot write the VCD"), std::string::npos) << e;
}

// ---- Derived times (machine_config.h, cost_model.h, units.h) ----

TEST(DerivedTimes, EachIsBoundedAtConfigurationNamingItsFlags) {
    auto bad = [](auto change, const std::string& mention) {
        MachineConfig m;
        change(m);
        SCOPED_TRACE(mention);
        const std::string e = thrown<std::invalid_argument>([&] { m.checkDerivedTimes(1000); });
        EXPECT_EQ(e.rfind(mention, 0), 0u) << e;
        EXPECT_NE(e.find("more than 1,000 s"), std::string::npos) << e;
    };
    bad([](MachineConfig& m) { m.link.bandwidth = 1e-6; }, "--link-bandwidth with --ray-batch");
    bad([](MachineConfig& m) { m.linkOverride[{{1, 0, 0}, 1}] = LinkParams{0, 1e-9, 16, 0, 0}; }, "--link-set 1,0,0,-x");
    bad([](MachineConfig& m) { m.fbPort.bandwidth = 1; m.fbBatch = 65536; }, "--fb-bandwidth with --fb-batch");
    bad([](MachineConfig& m) { m.hostCost = kMaxTimeValue; m.fbBatch = 65536; }, "--cost-host with --fb-batch");
    bad([](MachineConfig& m) { m.speed = 1e-15; }, "--speed 1e-15 with --cost-sphere");
    bad([](MachineConfig& m) { m.nodeSpeed[{0, 1, 0}] = 1e-12; }, "--node-speed 0,1,0=1e-12 with --cost-sphere");
    bad([](MachineConfig& m) { m.balance.policy = "slide"; m.balance.rebuildCost = kMaxTimeValue; }, "--cost-rebuild");
    bad([](MachineConfig& m) {
        m.balance.policy = "slide";
        m.link.bandwidth = 10;
        m.link.controlDepth = 2;
        m.balance.reportShare = 1e-6;
    }, "--link-bandwidth with --report-share");
    MachineConfig fine;
    fine.speed = 1e-9;  // 10 s a sphere test: slow, but a time the model can count
    EXPECT_NO_THROW(fine.checkDerivedTimes(1000));
}

TEST(DerivedTimes, ARunsSumsAreCheckedAsTheyAreMade) {
    Costs c;
    c.test = {kMaxTimeValue, 1, 1};
    Counters before, after;
    after.tests = {5000, 0, 0};  // 5,000 sphere tests of 1,000 s: past 2^62 ps
    EXPECT_NE(thrown<std::runtime_error>([&] { CostModel(c, 1.0, 0).step(before, after, 0, 0, 0); }).find("would wrap"),
              std::string::npos);
    after.tests = {4000, 0, 0};  // 4,000: within it, exact
    EXPECT_EQ(CostModel(c, 1.0, 0).step(before, after, 0, 0, 0), 4000 * kMaxTimeValue);
    // ... but not at half the speed.
    EXPECT_NE(thrown<std::runtime_error>([&] { CostModel(c, 0.5, 0).step(before, after, 0, 0, 0); }).find("speed factor"),
              std::string::npos);
    EXPECT_NE(thrown<std::runtime_error>([&] { CostModel(c, 1.0, kMaxTimeValue).rebuild(10000); }).find("--cost-rebuild"),
              std::string::npos);
    EXPECT_NE(thrown<std::runtime_error>([] { timesCount(Picos(1) << 40, uint64_t(1) << 30, "x"); }).find("x: "),
              std::string::npos);
    EXPECT_EQ(saturatedPicos(1e300), kMaxSimTime);
    EXPECT_EQ(saturatedPicos(std::nan("")), 0u);
    EXPECT_EQ(saturatedPicos(-5), 0u);
    EXPECT_EQ(saturatedPicos(12.9), 12u);  // (truncated, as the casts it replaces)
}

// ---- The grids' memory, counted before it is taken (grid.h) ----

TEST(GridSize, CountedBeforeBuildingIsWhatTheGridHolds) {
    std::vector<Shape> objects;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 300; ++i) {
        Shape s;
        s.geometry = Sphere{Vec3(u(rng), u(rng), u(rng)), i % 3 ? 0.02 : 0.6, false};  // a third of them overlapping much
        s.id = uint32_t(i);
        objects.push_back(s);
    }
    const Box box{Vec3(-0.7), Vec3(1.7)};
    const UniformGrid g(objects, box);
    const UniformGrid::Size size = UniformGrid::sizeFor(objects, box);
    uint64_t references = 0;
    const Lattice& l = g.lattice();
    for (int z = 0; z < l.cells(2); ++z)
        for (int y = 0; y < l.cells(1); ++y)
            for (int x = 0; x < l.cells(0); ++x) references += g.cellObjects({x, y, z}).size();
    EXPECT_EQ(size.references, references);
    EXPECT_EQ(size.cells, uint64_t(l.cellCount()));
}

// ---- What a job may use: physical memory, the cgroup, RLIMIT_AS (memory_estimate.h, job_memory.h) ----

TEST_F(Folder, TheCgroupsMemoryLimitIsTheLeastOfItsOwnAndItsParents) {
    fs::create_directories(dir_ / "v2/app/job");
    write("v2/memory.max", "max\n");
    write("v2/app/memory.max", "3221225472\n");  // 3 GiB
    write("v2/app/job/memory.max", "max\n");
    std::string file;
    EXPECT_EQ(cgroupMemoryLimit("0::/app/job\n", path("v2"), file), 3221225472.0);
    EXPECT_EQ(file, path("v2/app/memory.max"));
    EXPECT_EQ(cgroupMemoryLimit("0::/\n", path("v2"), file), 0);  // "max": none
    // v1: the memory controller's hierarchy; its "unlimited" is about 2^63.
    fs::create_directories(dir_ / "v1/memory/box");
    write("v1/memory/memory.limit_in_bytes", "9223372036854771712\n");
    write("v1/memory/box/memory.limit_in_bytes", "1073741824\n");
    EXPECT_EQ(cgroupMemoryLimit("5:cpu:/other\n4:memory:/box\n0::/\n", path("v1"), file), 1073741824.0);
    EXPECT_EQ(cgroupMemoryLimit("4:memory:/\n", path("v1"), file), 0);
    // A container sees a path of the host's that is not mounted: the root's limit.
    write("v2/memory.max", "2147483648\n");
    EXPECT_EQ(cgroupMemoryLimit("0::/host/slice\n", path("v2"), file), 2147483648.0);
    EXPECT_EQ(cgroupMemoryLimit("garbage\n\n0::relative\n", path("v2"), file), 0);
}

TEST(JobMemory, AJobIsCheckedAgainstEveryLimitAndCountsItsReferenceRuns) {
    constexpr double G = double(1 << 30);
    RtsimOptions o;
    CLI::App app;
    o.addTo(app);
    app.parse(std::vector<std::string>{"32", "--mesh", "8x8", "--size"});  // (reversed, as CLI11 takes them)
    o.finish();
    Scene scene = o.scene.load();
    const JobMemory j = jobMemory(o, scene);
    EXPECT_GT(j.frame, kRtsimBytesPerNode * 32 * 32 * 32);       // the nodes alone: about 1 GiB
    EXPECT_EQ(j.comparison, j.frame);                             // the same mesh, balanced the other way
    EXPECT_GT(j.baseline, 0);                                     // one node with every object
    EXPECT_LT(j.baseline, j.frame);
    const double frame = j.frame, all = j.together();
    MemoryLimits roomy{64 * G, 0, "", 0, 0};
    EXPECT_NO_THROW(checkJobMemory(o, scene, roomy));
    MemoryLimits as = roomy;  // ulimit -v: each process on its own, with what it has mapped already
    as.addressSpace = frame + 100e6;
    EXPECT_NO_THROW(checkJobMemory(o, scene, as));
    as.mapped = 200e6;
    EXPECT_NE(thrown<SceneError>([&] { checkJobMemory(o, scene, as); }).find("RLIMIT_AS"), std::string::npos);
    MemoryLimits cg = roomy;  // the cgroup: every process of the job at once
    cg.cgroup = (frame + all) / 2;
    cg.cgroupFile = "/sys/fs/cgroup/memory.max";
    EXPECT_NE(thrown<SceneError>([&] { checkJobMemory(o, scene, cg); }).find("its cgroup's limit is"), std::string::npos);
    o.baseline = false;  // --no-baseline: the frame alone
    EXPECT_NO_THROW(checkJobMemory(o, scene, cg));
    MemoryLimits small = roomy;
    small.physical = frame / 2;
    EXPECT_NE(thrown<SceneError>([&] { checkJobMemory(o, scene, small); }).find("this machine has"), std::string::npos);
}

TEST(Subprocess, AStopReachesAReferenceRunHoweverCloseToItsStartItComes) {
    // CI saw a SIGTERM land between "reference runs:" and the child's slot:
    // the 1x1x1 baseline then ran to its end (3.9 s under AddressSanitizer).
    using Clock = std::chrono::steady_clock;
    auto seconds = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
    stopSignal = SIGTERM;  // rtsim had a stop before the child started
    auto t0 = Clock::now();
    EXPECT_EQ(waitExit(spawn({"/bin/sleep", "20"}, false, "", true)), 128 + SIGTERM);
    EXPECT_LT(seconds(t0), 10);
    // A map drawn after a stopped run is not stopped;
    EXPECT_EQ(waitExit(spawn({"/bin/sh", "-c", "sleep 0.2; exit 7"}, false, "", false)), 7);
    stopSignal = 0;
    // a stop while it runs still reaches it (and it does not start with SIGTERM held).
    const pid_t map = spawn({"/bin/sleep", "20"}, false, "", false);
    ASSERT_GT(map, 0);
    t0 = Clock::now();
    signalChildrenNow(SIGTERM);
    EXPECT_EQ(waitExit(map), 128 + SIGTERM);
    EXPECT_LT(seconds(t0), 10);
    // rtsim's own mask is as it was: a SIGTERM is not left held.
    sigset_t now;
    sigprocmask(SIG_SETMASK, nullptr, &now);
    EXPECT_FALSE(sigismember(&now, SIGTERM));
    EXPECT_FALSE(sigismember(&now, SIGINT));
}
