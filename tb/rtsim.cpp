// rtsim: the machine, one frame. With no arguments it runs the paper's
// concentrated-spheres scene on a 4 x 4 x 4 mesh and prints a summary.
// Exit codes: 0 done, 2 bad input (one line naming the flag or file), 1 a
// failed run (a conservation law broken, a SystemC error).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <systemc>

#include "machine.h"
#include "nff_reader.h"
#include "report.h"
#include "rtsim_cli.h"
#include "scene_error.h"

// The allocator: jemalloc, told to back the heap with transparent huge
// pages. The model's data is spread over every node (its grid, objects, link
// buffers, stack) and a run visits them in turn, so most of its cost is
// memory access, not arithmetic; 2 MB pages cut the TLB misses and the page
// faults, about 9 % of the wall time on balls-4 at 512x512, N = 4
// (doc/exploration.md, "Performance"). jemalloc reads this at start-up.
extern "C" {
const char* malloc_conf = "thp:always,metadata_thp:always";
}

namespace {

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// The same run on a 1x1x1 mesh, in a child process (SystemC elaborates once
// per process): its render time, or a negative number if it failed.
double baselineRenderTimeNs(int argc, char** argv) {
    char tmpl[] = "/tmp/rtsim-baseline-XXXXXX";
    const int fd = mkstemp(tmpl);
    if (fd < 0) return -1;
    close(fd);
    char self[4096];
    const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0) return -1;
    self[n] = 0;
    std::string cmd = shellQuote(self);
    for (int i = 1; i < argc; ++i) cmd += " " + shellQuote(argv[i]);
    cmd += " --as-baseline --report " + shellQuote(tmpl) + " </dev/null >/dev/null";
    double t = -1;
    if (std::system(cmd.c_str()) == 0) {
        std::ifstream f(tmpl);
        try {
            t = nlohmann::json::parse(f).at("render_time_ns").get<double>();
        } catch (const std::exception&) {
        }
    }
    std::remove(tmpl);
    return t;
}

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
    pr("load per node", "load", false);
    const auto& t = report["totals"];
    std::printf("  messages         %llu ray, %llu contribution, %llu credit (%.3g MB on links and ports)\n",
                (unsigned long long)t["messages"]["ray"].get<uint64_t>(),
                (unsigned long long)t["messages"]["contributions"].get<uint64_t>(),
                (unsigned long long)t["messages"]["credit"].get<uint64_t>(),
                double(t["bytes"]["ray"].get<uint64_t>() + t["bytes"]["contributions"].get<uint64_t>() +
                       t["bytes"]["credit"].get<uint64_t>()) / 1e6);
    if (o.machine.balance.policy != rt::Policy::None)
        std::printf("  balancing        %s along %c: %zu slides; max / mean load %.2f; boundaries %s\n",
                    rt::policyName(o.machine.balance.policy), "xyz"[o.machine.balance.axis],
                    report["balance"]["slides"].get<size_t>(), report["balance"]["max_over_mean_load"].get<double>(),
                    report["balance"]["stability"].get<std::string>().c_str());
    std::printf("  wall clock       %.3f s%s\n", r.wallSeconds, o.image.empty() ? "" : ("; image " + o.image).c_str());
}

}  // namespace

int sc_main(int argc, char** argv) {
    CLI::App app{"rtsim: a SystemC model of the sliding-boundary ray-tracing multicomputer (one frame)"};
    rt::RtsimOptions o;
    o.addTo(app);
    try {
        app.parse(argc, argv);
        o.finish();
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::FileError& e) {
        std::cerr << "rtsim: error: --config: " << e.what() << "\n";
        return 2;
    } catch (const CLI::ParseError& e) {
        std::cerr << "rtsim: error: " << e.what() << "\n";
        return 2;
    }
    rt::Scene scene;
    try {
        scene = o.scene.load();
        o.scene.imageSize(scene, o.machine.width, o.machine.height);
    } catch (const std::exception& e) {  // a bad scene file or --size
        std::cerr << "rtsim: error: " << e.what() << "\n";
        return 2;
    }
    o.machine.showProgress = !o.quiet && isatty(2);
    const bool single = o.machine.dims == std::array<int, 3>{1, 1, 1};
    try {
        const rt::MachineResult r = rt::runMachine(scene, o.machine);
        nlohmann::json report = rt::machineReport(r, o.machine);
        double baselineNs = single ? report["render_time_ns"].get<double>() : -1;
        if (o.baseline && !single) {
            const auto t0 = std::chrono::steady_clock::now();
            baselineNs = baselineRenderTimeNs(argc, argv);
            report["baseline"]["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (baselineNs < 0) std::cerr << "rtsim: warning: the 1x1x1 baseline run failed; no speed-up\n";
        }
        if (baselineNs > 0) {
            report["baseline"]["render_time_ns"] = baselineNs;
            report["baseline"]["speedup"] = baselineNs / report["render_time_ns"].get<double>();
        }
        if (!o.image.empty()) rt::writePng(r.image, o.image);
        if (!o.report.empty()) {
            std::ofstream f(o.report);
            f << report.dump(2) << "\n";
            if (!f) throw std::runtime_error(o.report + ": cannot write the report");
        }
        if (!o.quiet) printSummary(scene, o, r, report, baselineNs);
    } catch (const std::exception& e) {
        std::cerr << "rtsim: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}

int main(int argc, char** argv) {
    setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 0);
    // A SystemC warning is a failed run, not a line to scroll past.
    sc_core::sc_report_handler::set_actions(sc_core::SC_WARNING, sc_core::SC_DISPLAY | sc_core::SC_THROW);
    // The host ends the frame with sc_stop(); that is not news.
    sc_core::sc_report_handler::set_actions("/OSCI/SystemC", sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
    return sc_core::sc_elab_and_sim(argc, argv);
}
