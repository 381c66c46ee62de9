// rtsim: the machine, one frame. With no arguments it runs the paper's
// concentrated-spheres scene on a 4 x 4 x 4 mesh and prints a summary.
// Exit codes: 0 done, 2 bad input (one line naming the flag or file), 1 a
// failed run (a conservation law broken, a SystemC error), 3 stopped by the
// watchdog (in any frame of a --frames sequence; the report so far is written).
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>
#include <systemc>

#include "machine.h"
#include "memory_estimate.h"
#include "nff_reader.h"
#include "output_file.h"
#include "report.h"
#include "resplit.h"
#include "trace_writer.h"
#include "messages.h"
#include "rerun.h"
#include "rtsim_cli.h"
#include "subprocess.h"
#include "version.h"
#include "scene_error.h"

// The allocator: jemalloc, told to back the heap with transparent huge
// pages. The model's data is spread over every node (its grid, objects, link
// buffers, stack) and a run visits them in turn, so most of its cost is
// memory access, not arithmetic; 2 MB pages cut the TLB misses and the page
// faults, about 9 % of the wall time on balls-4 at 512x512, N = 4
// (doc/exploration.md, "Performance"). Freed pages go back to the system
// over 30 s rather than the default 10: a link's backlog grows to tens of
// megabytes, runs empty and grows again, and each time it found pages
// given back and the kernel had to zero fresh ones (7 % of that run's wall
// time, in clear_page; 5 % faster with the longer decay, the same peak
// memory). jemalloc reads this at start-up.
extern "C" {
const char* malloc_conf = "thp:always,metadata_thp:always,dirty_decay_ms:30000,muzzy_decay_ms:30000";
}

namespace {

// Each column's inner boundaries where the run of report `r` ended them
// (their last positions in the boundary histories), for MachineConfig::
// startBoundaries; with `atStart`, where they stood when it began (the
// first positions). Throws std::runtime_error if the report is of another
// mesh or axis.
std::vector<std::vector<double>> lastBoundaries(const nlohmann::json& r, const rt::MachineConfig& m,
                                                bool atStart = false) {
    const int ax = m.balance.axis, u = (ax + 1) % 3, v = (ax + 2) % 3, n = m.dims[size_t(ax)];
    try {
        const auto dims = r.at("config").at("mesh").get<std::array<int, 3>>();
        const std::string axis = r.at("config").at("balance").at("axis").get<std::string>();
        if (dims != m.dims || axis != std::string(1, "xyz"[ax]))
            throw std::runtime_error("its run is of another mesh or progress axis");
        std::vector<std::vector<double>> b(size_t(m.dims[size_t(u)] * m.dims[size_t(v)]),
                                           std::vector<double>(size_t(n - 1), std::nan("")));
        for (const auto& h : r.at("boundaries")) {
            const auto col = h.at("column").get<std::array<int, 2>>();
            const int k = h.at("index").get<int>();
            if (col[0] < 0 || col[0] >= m.dims[size_t(u)] || col[1] < 0 || col[1] >= m.dims[size_t(v)] || k < 1 || k >= n)
                throw std::runtime_error("a boundary outside the mesh");
            const auto& history = h.at("history");
            b[size_t(col[0] + m.dims[size_t(u)] * col[1])][size_t(k - 1)] =
                (atStart ? history.front() : history.back()).at(1).get<double>();
        }
        for (const auto& c : b)
            for (double x : c)
                if (!std::isfinite(x)) throw std::runtime_error("a boundary missing from its history");
        return b;
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(std::string("not an rtsim report (") + e.what() + ")");
    }
}

// `resplit`: each column's inner planes at the quantiles of its nodes' busy
// time in the run of report `r` (models/resplit.h), each node's busy time
// spread over its box as it stood on average over that frame.
std::vector<std::vector<double>> resplitTargets(const nlohmann::json& r, const rt::MachineConfig& m) {
    const std::vector<std::vector<double>> check = lastBoundaries(r, m);  // the same mesh and axis
    const int ax = m.balance.axis, u = (ax + 1) % 3, v = (ax + 2) % 3, n = m.dims[size_t(ax)];
    try {
        const double end = r.at("render_time_ns").get<double>();
        double lo = 1e300, hi = -1e300;
        std::vector<std::vector<double>> busy(check.size(), std::vector<double>(size_t(n), 0.0));
        for (const auto& node : r.at("nodes")) {
            const auto c = node.at("node").get<std::array<int, 3>>();
            const auto box = node.at("box").get<std::array<std::array<double, 3>, 2>>();
            lo = std::min(lo, box[0][size_t(ax)]);
            hi = std::max(hi, box[1][size_t(ax)]);
            busy.at(size_t(c[size_t(u)] + m.dims[size_t(u)] * c[size_t(v)])).at(size_t(c[size_t(ax)])) =
                node.at("busy_ns").get<double>();
        }
        std::vector<std::vector<double>> edges(check.size(), std::vector<double>(size_t(n + 1), 0.0));
        for (auto& e : edges) {
            e.front() = lo;
            e.back() = hi;
        }
        for (const auto& h : r.at("boundaries")) {
            const auto col = h.at("column").get<std::array<int, 2>>();
            std::vector<std::pair<double, double>> history;
            for (const auto& p : h.at("history")) history.push_back({p.at(0).get<double>(), p.at(1).get<double>()});
            edges[size_t(col[0] + m.dims[size_t(u)] * col[1])][size_t(h.at("index").get<int>())] =
                rt::timeAveraged(history, end);
        }
        const double minThickness = m.balance.minThickness * (hi - lo) / n;
        std::vector<std::vector<double>> targets;
        for (size_t c = 0; c < edges.size(); ++c) targets.push_back(rt::resplitPlanes(edges[c], busy[c], minThickness));
        return targets;
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(std::string("not an rtsim report (") + e.what() + ")");
    }
}

// `resplit` over a sequence of frames: what the next frame does. Each frame
// re-splits at the quantiles of the one before, as long as that keeps making
// frames faster:
//  - a re-split frame slower than the fastest re-split frame so far, when
//    that one beat the first frame, returns the boundaries to its planes,
//    and they hold from then on (equal busy times are not always the fastest
//    frame: across the axis the frame also waits for work to arrive, and
//    re-splitting to equal busy times crept from 825 to 953 us over ten
//    frames);
//  - if neither of the first two re-split frames beats the first frame,
//    re-splitting does not pay here (past the links' knee thinner boxes
//    cost more link time than they save: 1.3 to 1.8 times the first frame
//    at 3 us or 100 MB/s). (Two tries, not one: a first re-split a few per
//    cent slower than the first frame is often followed by faster ones.)
//    Then one frame holds the split the first frame started from: where
//    even the first frame's slides lose (1987 links at 360 KB/s: 1.14
//    times the unbalanced frame), that one wins and is held; otherwise
//    every later frame is the first one again.
class ResplitSequence {
public:
    explicit ResplitSequence(const rt::MachineConfig& m) : m_(m) {}
    // After frame `frame` (1-based), whose report is `r`: the next frame's
    // targets, or nothing if the next frame is to be the first one again.
    std::optional<std::vector<std::vector<double>>> next(const nlohmann::json& r, int frame) {
        afresh_ = false;
        if (again_) return std::nullopt;
        if (held_) return held_;
        const double t = r.at("render_time_ns").get<double>();
        if (frame == 1) {
            firstNs_ = t;
            start_ = lastBoundaries(r, m_, true);
            return resplitTargets(r, m_);
        }
        if (tryingStart_) {  // the frame just run held the starting split
            if (t < firstNs_) {
                held_ = start_;
                return held_;
            }
            again_ = true;
            return std::nullopt;
        }
        ++resplits_;
        const bool faster = t <= bestNs_;
        if (faster) {
            bestNs_ = t;
            best_ = r;
        }
        if (bestNs_ > firstNs_) {  // no re-split frame has beaten the first yet
            if (resplits_ >= kTries) {
                tryingStart_ = afresh_ = true;
                return start_;
            }
            return resplitTargets(r, m_);
        }
        if (!faster) {
            held_ = lastBoundaries(best_, m_);
            return held_;
        }
        return resplitTargets(r, m_);
    }

    // Whether the next frame starts where frame 1 did (the starting split's
    // trial), not where the frame before left the boundaries: in a steady
    // state the faces would be moved back once, and that frame is to show
    // the split itself.
    bool startsAfresh() const { return afresh_; }

private:
    static constexpr int kTries = 2;
    const rt::MachineConfig& m_;
    double firstNs_ = 0, bestNs_ = 1e300;  // the first frame's time; the fastest re-split frame's
    int resplits_ = 0;                     // re-split frames so far
    nlohmann::json best_;
    std::vector<std::vector<double>> start_;  // where frame 1's boundaries started
    std::optional<std::vector<std::vector<double>>> held_;
    bool tryingStart_ = false, again_ = false, afresh_ = false;
};

// Writes `j` to a fresh temporary file; its path.
std::string tempJson(const nlohmann::json& j) { return rt::makeTempFile("rtsim-frame", j.dump() + "\n"); }

struct Spread {
    double min, mean, max;
};
template <class F>
Spread spread(const rt::MachineResult& r, F f) {
    Spread s{1e300, 0, -1e300};
    for (size_t i = 0; i < r.nodes.size(); ++i) {
        const double v = f(i);
        s.min = std::min(s.min, v);
        s.max = std::max(s.max, v);
        s.mean += v / double(r.nodes.size());
    }
    return s;
}

void printSummary(const rt::Scene& scene, const rt::RtsimOptions& o, const rt::MachineResult& r,
                  const nlohmann::json& report, double baselineNs) {
    const auto& d = o.machine.dims;
    const double renderNs = report["render_time_ns"].get<double>();
    std::printf("rtsim: %s (%zu objects), %dx%dx%d mesh, %dx%d image\n", scene.name.c_str(), scene.objects.size(), d[0],
                d[1], d[2], r.image.width, r.image.height);
    std::printf("  render time      %s", rt::formatTime(r.renderTime).c_str());
    if (baselineNs > 0)
        std::printf("   (1x1x1 with the same costs: %s, speed-up %.2f)",
                    rt::formatTime(rt::Picos(baselineNs * 1000 + 0.5)).c_str(), baselineNs / renderNs);
    std::printf("\n");
    const auto& nodes = report["nodes"];
    auto pr = [&](const char* label, const char* key, bool time) {
        const Spread s = spread(r, [&](size_t i) { return nodes[i][key].get<double>(); });
        if (time)
            std::printf("  %-16s min %s  mean %s  max %s\n", label, rt::formatTime(rt::Picos(s.min * 1000)).c_str(),
                        rt::formatTime(rt::Picos(s.mean * 1000)).c_str(), rt::formatTime(rt::Picos(s.max * 1000)).c_str());
        else
            std::printf("  %-16s min %.3f  mean %.3f  max %.3f  (max / mean %.2f)\n", label, s.min, s.mean, s.max,
                        s.mean > 0 ? s.max / s.mean : 0.0);
    };
    pr("busy per node", "busy_ns", true);
    pr("wait per node", "wait_ns", true);
    if (report["totals"]["blocked_ns"].get<double>() > 0) pr("  of it blocked", "blocked_ns", true);  // full output buffers
    pr("load per node", "load", false);
    const auto& fb = report["frame_buffer"];
    std::printf("  frame buffer     %zu unit%s, busiest %s busy (%.1f %% of the render time)\n", fb["units"].size(),
                fb["units"].size() == 1 ? "" : "s", rt::formatTime(rt::Picos(fb["busy_ns"].get<double>() * 1000)).c_str(),
                100.0 * report["bounds"]["frame_buffer"]["fraction"].get<double>());
    const auto& t = report["totals"];
    std::printf("  messages         %llu ray, %llu contribution, %llu credit (%.3g MB on links and ports)\n",
                (unsigned long long)t["messages"]["ray"].get<uint64_t>(),
                (unsigned long long)t["messages"]["contributions"].get<uint64_t>(),
                (unsigned long long)t["messages"]["credit"].get<uint64_t>(),
                double(t["bytes"]["ray"].get<uint64_t>() + t["bytes"]["contributions"].get<uint64_t>() +
                       t["bytes"]["credit"].get<uint64_t>()) / 1e6);
    if (!report["busiest_links"].empty()) {  // where the wires are busiest: the hot links
        std::printf("  busiest links   ");
        for (const auto& l : report["busiest_links"])
            std::printf(" %s %.1f %%", l["name"].get<std::string>().c_str(), 100.0 * l["utilisation"].get<double>());
        std::printf("  (wire busy, of the render time)\n");
    }
    const char axis = "xyz"[o.machine.balance.axis];
    if (o.machine.balance.policy != "none") {
        std::printf("  balancing        %s along %c: %zu slides; max / mean load %.2f; boundaries %s\n",
                    o.machine.balance.policy.c_str(), axis, report["balance"]["slides"].get<size_t>(),
                    report["balance"]["max_over_mean_load"].get<double>(),
                    report["balance"]["stability"].get<std::string>().c_str());
        const auto& b = report["bounds"];
        auto bound = [&](const char* k) {
            return rt::formatTime(rt::Picos(b[k]["ns"].get<double>() * 1000)) + " (" +
                   std::to_string(b[k]["fraction"].get<double>()).substr(0, 4) + ")";
        };
        std::printf("  bounds           perfect %s, column along %c %s, frame buffer %s (fractions of the render time)\n",
                    bound("perfect").c_str(), axis, bound("column").c_str(), bound("frame_buffer").c_str());
    }
    if (report.contains("comparison")) {  // the paper's Fig. 4 quantity for this frame
        const auto& c = report["comparison"];
        std::printf("  with / without   %s: %s, none: %s; ratio %.2f (bound %.2f: the heaviest column along %c spread "
                    "evenly; paper about 0.2 at f = 1/N)\n",
                    c["balanced_policy"].get<std::string>().c_str(),
                    rt::formatTime(rt::Picos(c["balanced_ns"].get<double>() * 1000)).c_str(),
                    rt::formatTime(rt::Picos(c["unbalanced_ns"].get<double>() * 1000)).c_str(),
                    c["ratio"].get<double>(), c["column_bound"].get<double>(), axis);
    }
    if (report.contains("frames")) {
        std::printf("  frames          ");
        for (const auto& f : report["frames"])
            std::printf(" %s", rt::formatTime(rt::Picos(f["render_time_ns"].get<double>() * 1000)).c_str());
        std::printf("  (render times; the figures above are the last frame's)\n");
    }
    std::printf("  wall clock       %.3f s%s\n", r.wallSeconds, o.image.empty() ? "" : ("; image " + o.image).c_str());
}

// --map: scripts/mesh_map.py draws the run's report (written to a
// temporary file if the run writes none).
void drawMap(const std::string& reportText, const std::string& reportPath, const std::string& out) {
    const std::string path = reportPath.empty() ? rt::makeTempFile("rtsim-map", reportText) : reportPath;
    const int code = rt::waitExit(
        rt::spawn({"/usr/bin/python3", std::string(RT_SCRIPTS_DIR) + "/mesh_map.py", path, "-o", out}, true));
    if (reportPath.empty()) std::remove(path.c_str());
    if (code != 0)
        throw std::runtime_error("--map: scripts/mesh_map.py failed (it needs /usr/bin/python3 and python3-matplotlib: "
                                 "scripts/setup.sh)");
}

// The settings the machine's config does not hold: the scene (its file
// and SHA-256, or the procedural parameters), the camera and lights as this
// frame sees them, the frame sequence and the version.
void runSettings(nlohmann::json& c, const rt::RtsimOptions& o, const rt::Scene& scene) {
    auto vec = [](const rt::Vec3& v) { return nlohmann::json{v.x, v.y, v.z}; };
    auto& s = c["scene"];
    s["objects"] = scene.objects.size();
    if (!o.scene.file.empty()) {
        s["file"] = std::filesystem::absolute(o.scene.file).lexically_normal().string();
        s["sha256"] = rt::sha256OfFile(o.scene.file);
    } else {
        const rt::ProceduralParams& p = o.scene.procedural;
        s["procedural"] = {{"spheres", p.spheres}, {"radius", p.radius}, {"concentration", p.concentration},
                           {"seed", p.seed}};
    }
    s["axis"] = o.scene.axis;
    c["camera"] = {{"eye", vec(scene.view.from)}, {"look_at", vec(scene.view.at)}, {"up", vec(scene.view.up)},
                   {"fov_deg", scene.view.angle}};
    for (const rt::Light& l : scene.lights) c["lights"].push_back({{"position", vec(l.position)}, {"colour", vec(l.colour)}});
    c["frames"] = {{"count", o.frames}, {"index", o.frameIndex}, {"eye_step", o.eyeStep}};
    if (!o.boundariesFrom.empty())
        c["frames"]["boundaries_from"] = std::filesystem::absolute(o.boundariesFrom).lexically_normal().string();
}

// The first setting where two configs differ, as "PATH: A there, B here";
// empty if none does.
std::string firstDifference(const nlohmann::json& there, const nlohmann::json& here) {
    for (const nlohmann::json& op : nlohmann::json::diff(there, here)) {
        const std::string path = op["path"].get<std::string>();
        const nlohmann::json a = there.contains(nlohmann::json::json_pointer(path)) ? there[nlohmann::json::json_pointer(path)] : nlohmann::json();
        const nlohmann::json b = here.contains(nlohmann::json::json_pointer(path)) ? here[nlohmann::json::json_pointer(path)] : nlohmann::json();
        return path + ": " + a.dump() + " there, " + b.dump() + " here";
    }
    return "";
}

}  // namespace

int sc_main(int argc, char** argv) {
    CLI::App app{"rtsim: a SystemC model of the sliding-boundary ray-tracing multicomputer (one frame, or a sequence with --frames)"};
    rt::RtsimOptions o;
    o.addTo(app);
    std::optional<rt::Rerun> rerun;  // --rerun REPORT.json: its flags, then those given after (rerun.h)
    // (The level --verbose gives, before parsing: a bad flag says its ID too.)
    int verbose = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--verbose") ++verbose;
        else if (a.size() >= 2 && a[0] == '-' && a[1] == 'v' && a.find_first_not_of('v', 1) == std::string::npos)
            verbose += int(a.size()) - 1;
    }
    rt::msg::install(verbose);
    try {
        rerun = rt::prepareRerun(argc, argv);
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kConfig, e.what());
        return 2;
    }
    try {
        if (rerun) {
            std::vector<std::string> args{argv[0]};
            args.insert(args.end(), rerun->args.begin(), rerun->args.end());
            std::vector<char*> av;
            for (std::string& a : args) av.push_back(a.data());
            app.parse(int(av.size()), av.data());
        } else {
            app.parse(argc, argv);
        }
        o.finish();
        rt::msg::install(o.verbose);  // (0 in a reference run)
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::FileError& e) {
        rt::msg::error(rt::msg::kConfig, std::string("--config: ") + e.what());
        return 2;
    } catch (const CLI::ParseError& e) {
        rt::msg::error(rt::msg::kConfig, e.what());
        return 2;
    }
    rt::Scene scene;
    try {
        // Outputs first: a path that cannot be written is found now, not
        // after the run.
        if (!o.image.empty()) rt::checkWritable("--image", o.image);
        if (!o.report.empty()) rt::checkWritable("--report", o.report);
        if (!o.map.empty()) rt::checkWritable("--map", o.map);
        if (!o.vcd.empty()) {
            rt::checkWritable("--vcd", o.vcd);
            rt::checkWritable("--vcd", rt::gtkwPathFor(o.vcd));
        }
        scene = o.scene.load();
        o.scene.imageSize(scene, o.machine.width, o.machine.height);
        try {
            rt::refuseIfTooBig("--size " + std::to_string(o.machine.width) + "x" + std::to_string(o.machine.height),
                               rt::kRtsimBytesPerPixel * o.machine.width * o.machine.height);
        } catch (const rt::SceneError& e) {
            throw std::invalid_argument(e.what());  // (a flag's value, not the scene)
        }
    } catch (const rt::OutputError& e) {
        rt::msg::error(rt::msg::kOutput, e.what());
        return 2;
    } catch (const rt::SceneError& e) {
        rt::msg::error(rt::msg::kScene, e.what());
        return 2;
    } catch (const std::exception& e) {  // --size
        rt::msg::error(rt::msg::kConfig, e.what());
        return 2;
    }
    // A frame of a camera path: the eye moved frameIndex steps.
    if (!o.eyeStep.empty())
        scene.view.from = scene.view.from + rt::Vec3(o.eyeStep[0], o.eyeStep[1], o.eyeStep[2]) * double(o.frameIndex);
    // Every setting as this run uses it (the report's `config`); a rerun
    // without flags of its own must arrive at the report's.
    nlohmann::json config = rt::machineConfigJson(o.machine, o.machine.width, o.machine.height);
    try {
        runSettings(config, o, scene);
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kScene, e.what());
        return 2;
    }
    if (rerun && !rerun->overrides && !o.asBaseline && !o.asComparison && !o.asFrame) {  // (a reference run differs by design)
        const std::string differs = firstDifference(rerun->report["config"], config);
        if (!differs.empty()) {
            rt::msg::error(rt::msg::kConfig, "--rerun: this build arrives at other settings than the report's: " + differs);
            return 2;
        }
    }
    try {  // a run that continues another's boundaries
        if (!o.boundariesFrom.empty()) {
            std::ifstream f(o.boundariesFrom);
            nlohmann::json prev;
            try {
                prev = nlohmann::json::parse(f);
            } catch (const std::exception&) {
                throw std::runtime_error("not JSON");
            }
            o.machine.startBoundaries = lastBoundaries(prev, o.machine);
            if (o.machine.balance.policy == "resplit") o.machine.targetBoundaries = resplitTargets(prev, o.machine);
        }
        if (!o.targetsFrom.empty()) {  // a frame of a sequence: the targets its frame loop chose
            std::ifstream f(o.targetsFrom);
            o.machine.targetBoundaries = nlohmann::json::parse(f).get<std::vector<std::vector<double>>>();
        }
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kConfig, "--boundaries-from " + o.boundariesFrom + ": " + e.what());
        return 2;
    }
    if (rerun)
        rt::msg::info("running again the flags of a report written by " +
                      rerun->report["rerun"].value("version", std::string("an unknown build")) + " (this is " RTSIM_VERSION ")" +
                      (rerun->overrides ? ", with the flags given after --rerun on top" : ""));
    rt::msg::info((o.machine.lookaheadQuantum ? "quantum: each process's lookahead (the smallest " +
                                                    rt::formatTime(o.machine.lookahead()) + ")"
                                              : "quantum " + rt::formatTime(o.machine.quantum) + " (lookahead " +
                                                    rt::formatTime(o.machine.lookahead()) + ")") +
                  "; watchdog after " + rt::formatTime(o.machine.watchdogSpanOrDefault(scene.objects.size())) +
                  " of simulated time without progress");
    o.machine.showProgress = !o.quiet && isatty(2);
    const bool single = o.machine.dims == std::array<int, 3>{1, 1, 1};
    try {
        // The frames before the last, one child process each (SystemC
        // elaborates once per process), in turn: each starts where the one
        // before left the boundaries (static policies start each frame at
        // their own positions).
        nlohmann::json frames = nlohmann::json::array();
        const bool carry = o.machine.balance.dynamic(), resplit = o.machine.balance.policy == "resplit";
        ResplitSequence sequence(o.machine);
        const rt::MachineConfig first = o.machine;  // how frame 1 starts
        bool again = false;                         // resplit: every later frame is the first one again
        bool afresh = false;                        // resplit: the next frame starts where frame 1 did
        for (int k = 0; k + 1 < o.frames; ++k) {
            std::vector<std::string> extra{"--as-frame", "--frame-index", std::to_string(k)};
            std::string from, targets;
            // (Frame 1, a frame that is the first one again and the starting
            // split's trial start where the user said: --boundaries-from, or
            // the policy's start.)
            if (carry && k > 0 && !again && !afresh) {
                from = tempJson(frames.back().at("report"));
                extra.insert(extra.end(), {"--boundaries-from", from});
            }
            if (resplit && k > 0 && !again) {
                targets = tempJson(o.machine.targetBoundaries);
                extra.insert(extra.end(), {"--targets-from", targets});
            }
            rt::Child child(argc, argv, extra);
            const std::optional<nlohmann::json> f = child.report(), stopped = child.stoppedReport();
            if (!from.empty()) std::remove(from.c_str());
            if (!targets.empty()) std::remove(targets.c_str());
            const std::string which = "frame " + std::to_string(k + 1) + " of " + std::to_string(o.frames);
            if (stopped) {
                // The watchdog stopped an earlier frame (the child said why on
                // stderr): its report so far, with the frames before it, and
                // exit 3 as for the last frame. No image, no VCD (those are of
                // the last frame).
                nlohmann::json report = *stopped;
                for (auto& f : frames) f.erase("report");
                frames.push_back({{"frame", k + 1}, {"render_time_ns", report["render_time_ns"]},
                                  {"slides", report["balance"].value("slides", 0)}, {"incomplete", true}});
                report["frames"] = frames;
                report["incomplete"] = which + ": " + report.value("incomplete", std::string());
                if (!o.report.empty()) {
                    rt::AtomicFile out(o.report);
                    out.write(report.dump(2) + "\n");
                    out.commit();
                }
                return 3;
            }
            if (!f) throw std::runtime_error(which + " failed");
            frames.push_back({{"frame", k + 1}, {"render_time_ns", (*f)["render_time_ns"]},
                              {"slides", (*f)["balance"].value("slides", 0)}, {"report", *f}});
            if (carry) o.machine.startBoundaries = lastBoundaries(*f, o.machine);
            if (resplit) {
                const auto next = sequence.next(*f, k + 1);
                if (next) {
                    o.machine.targetBoundaries = *next;
                    afresh = sequence.startsAfresh();
                    if (afresh) o.machine.startBoundaries = first.startBoundaries;
                } else {
                    again = true;
                    o.machine.startBoundaries = first.startBoundaries;
                    o.machine.targetBoundaries = first.targetBoundaries;
                }
            }
        }
        const rt::MachineResult r = rt::runMachine(scene, o.machine);
        nlohmann::json report = rt::machineReport(r, o.machine);
        report["config"] = config;
        report["rerun"] = {{"flags", rt::flagsGiven(app)}, {"version", RTSIM_VERSION}};
        if (rerun) report["rerun"]["of"] = rerun->report["rerun"];  // what it reran
        if (o.frames > 1) {
            frames.push_back({{"frame", o.frames}, {"render_time_ns", report["render_time_ns"]},
                              {"slides", report["balance"].value("slides", 0)}});
            for (auto& f : frames) f.erase("report");
            report["frames"] = frames;
        }
        if (!r.incomplete.empty()) {  // the watchdog stopped it: the report so far (the VCD is written), exit 3
            if (!o.report.empty()) {
                rt::AtomicFile f(o.report);
                f.write(report.dump(2) + "\n");
                f.commit();
            }
            if (rt::stopSignal) {  // Ctrl-C or kill: as a shell reports a signal, 128 + its number
                rt::msg::note(rt::msg::kSignal, r.incomplete);
                return 128 + int(rt::stopSignal);
            }
            rt::msg::error(rt::msg::kWatchdog, "watchdog: " + r.incomplete);
            return 3;
        }
        double baselineNs = single ? report["render_time_ns"].get<double>() : -1;
        // The reference runs, in two child processes at once: the 1x1x1 mesh
        // (the speed-up), and the same frame balanced the other way (with the
        // default policy if this run does not balance, without otherwise).
        const std::string policy = o.machine.balance.policy;
        const bool compare = o.baseline && o.machine.dims[size_t(o.machine.balance.axis)] > 1;
        std::optional<nlohmann::json> base, other;
        const auto t0 = std::chrono::steady_clock::now();
        std::optional<rt::Child> baseRun, otherRun;
        if (o.baseline && !single) rt::msg::info("reference runs: the 1x1x1 baseline" + std::string(compare ? " and the balancing comparison" : "") + ", in child processes");
        if (o.baseline && !single) baseRun.emplace(argc, argv, std::vector<std::string>{"--as-baseline"});
        if (compare)
            otherRun.emplace(argc, argv,
                             std::vector<std::string>{"--as-comparison", "--balance", policy == "none" ? "default" : "none"});
        if (baseRun) base = baseRun->report();
        if (otherRun) other = otherRun->report();
        if (o.baseline && !single) {
            report["baseline"]["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (base) baselineNs = (*base)["render_time_ns"].get<double>();
            else rt::msg::warning(rt::msg::kReference, "the 1x1x1 baseline run failed; no speed-up");
        }
        if (baselineNs > 0) {
            report["baseline"]["render_time_ns"] = baselineNs;
            report["baseline"]["speedup"] = baselineNs / report["render_time_ns"].get<double>();
        }
        if (compare && !other) rt::msg::warning(rt::msg::kReference, "the balancing comparison run failed; no ratio");
        if (other) {
            const nlohmann::json& balanced = policy == "none" ? *other : report;
            const nlohmann::json& unbalanced = policy == "none" ? report : *other;
            report["comparison"] = {
                {"balanced_policy", balanced["config"]["balance"]["policy"]},
                {"balanced_ns", balanced["render_time_ns"]},
                {"unbalanced_ns", unbalanced["render_time_ns"]},
                {"ratio", balanced["render_time_ns"].get<double>() / unbalanced["render_time_ns"].get<double>()},
                // The bounds of the unbalanced run, as fractions of its time:
                // what the ratio could at best be.
                {"column_bound", unbalanced["bounds"]["column"]["fraction"]},
                {"perfect_bound", unbalanced["bounds"]["perfect"]["fraction"]}};
        }
        // Written whole or not at all (output_file.h): each to a temporary
        // file, renamed over its path once all are written.
        std::optional<rt::AtomicFile> image, reportFile;
        if (!o.image.empty()) {
            image.emplace(o.image);
            rt::writePng(r.image, image->temp());
        }
        if (!o.report.empty()) {
            reportFile.emplace(o.report);
            reportFile->write(report.dump(2) + "\n");
        }
        if (image) image->commit();
        if (reportFile) reportFile->commit();
        if (!o.map.empty()) drawMap(o.report.empty() ? report.dump() : std::string(), o.report, o.map);
        if (!o.quiet) printSummary(scene, o, r, report, baselineNs);
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kRun, e.what());
        if (!o.vcd.empty()) {  // a failed run leaves no waveform that looks like a result
            std::remove(o.vcd.c_str());
            std::remove(rt::gtkwPathFor(o.vcd).c_str());
        }
        return 1;
    }
    return 0;
}

extern "C" void onStopSignal(int sig) { rt::stopSignal = sig; }

int main(int argc, char** argv) {
    setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 0);
    // Ctrl-C (or SIGTERM) stops the run at the watchdog's next wake, with
    // the report and VCD so far; a second one ends it at once.
    struct sigaction stop {};
    stop.sa_handler = onStopSignal;
    stop.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &stop, nullptr);
    sigaction(SIGTERM, &stop, nullptr);
    // A SystemC warning is a failed run, not a line to scroll past.
    sc_core::sc_report_handler::set_actions(sc_core::SC_WARNING, sc_core::SC_DISPLAY | sc_core::SC_THROW);
    // The host ends the frame with sc_stop(); that is not news.
    sc_core::sc_report_handler::set_actions("/OSCI/SystemC", sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
    return sc_core::sc_elab_and_sim(argc, argv);
}
