// rtsim: the machine, one frame. With no arguments it runs the paper's
// concentrated-spheres scene on a 4 x 4 x 4 mesh and prints a summary.
// Exit codes: 0 done, 2 bad input (one line naming the flag or file), 1 a
// failed run (a conservation law broken, a SystemC error), 3 stopped by the
// watchdog (in any frame of a --frames sequence; the report so far is
// written), 128 + N stopped by signal N.
//
// sc_main reads the command line, then takes the run's steps in turn:
// the scene, the settings echoed into the report, the boundaries a frame
// starts from, the earlier frames of a sequence (frame_sequence.h), the
// machine itself (models/machine.h), the reference runs
// (reference_runs.h), the outputs (outputs.h) and the summary (summary.h).
#include <signal.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <systemc>

#include "between_frames.h"
#include "config_echo.h"
#include "frame_sequence.h"
#include "machine.h"
#include "memory_estimate.h"
#include "messages.h"
#include "output_file.h"
#include "outputs.h"
#include "reference_runs.h"
#include "report.h"
#include "rerun.h"
#include "rtsim_cli.h"
#include "scene_error.h"
#include "summary.h"
#include "version.h"

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

// A step that ends the program returns its exit code; one that lets the
// run go on returns nothing.
using Stop = std::optional<int>;

// The command line (or a report's, with --rerun): parsed and checked.
Stop readCommandLine(CLI::App& app, rt::RtsimOptions& o, std::optional<rt::Rerun>& rerun, int argc, char** argv) {
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
    return std::nullopt;
}

// The outputs checked (before the run, not after it), the scene read, the
// image's size checked against the machine's memory.
Stop loadScene(rt::RtsimOptions& o, rt::Scene& scene) {
    try {
        rt::checkOutputs(o);
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
    return std::nullopt;
}

// Every setting as this run uses it (the report's `config`); a rerun
// without flags of its own must arrive at the report's.
Stop echoConfig(const rt::RtsimOptions& o, const rt::Scene& scene, const std::optional<rt::Rerun>& rerun,
                nlohmann::json& config) {
    try {
        config = rt::configEcho(o, scene);
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kScene, e.what());
        return 2;
    }
    if (rerun && !rerun->overrides && !o.asBaseline && !o.asComparison && !o.asFrame) {  // (a reference run differs by design)
        const std::string differs = rt::firstDifference(rerun->report["config"], config);
        if (!differs.empty()) {
            rt::msg::error(rt::msg::kConfig, "--rerun: this build arrives at other settings than the report's: " + differs);
            return 2;
        }
    }
    return std::nullopt;
}

// A run that continues another's boundaries (--boundaries-from), or a frame
// of a sequence with the targets its frame loop chose (--targets-from).
Stop startBoundaries(rt::RtsimOptions& o) {
    try {
        if (!o.boundariesFrom.empty()) {
            std::ifstream f(o.boundariesFrom);
            nlohmann::json prev;
            try {
                prev = nlohmann::json::parse(f);
            } catch (const std::exception&) {
                throw std::runtime_error("not JSON");
            }
            o.machine.startBoundaries = rt::lastBoundaries(prev, o.machine);
            if (o.machine.balance.policy == "resplit") o.machine.targetBoundaries = rt::resplitTargets(prev, o.machine);
        }
        if (!o.targetsFrom.empty()) {
            std::ifstream f(o.targetsFrom);
            o.machine.targetBoundaries = nlohmann::json::parse(f).get<std::vector<std::vector<double>>>();
        }
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kConfig, "--boundaries-from " + o.boundariesFrom + ": " + e.what());
        return 2;
    }
    return std::nullopt;
}

void sayWhatRuns(const rt::RtsimOptions& o, const std::optional<rt::Rerun>& rerun, const rt::Scene& scene) {
    if (rerun)
        rt::msg::info("running again the flags of a report written by " +
                      rerun->report["rerun"].value("version", std::string("an unknown build")) + " (this is " RTSIM_VERSION ")" +
                      (rerun->overrides ? ", with the flags given after --rerun on top" : ""));
    const rt::MachineConfig& m = o.machine;
    rt::msg::info((m.lookaheadQuantum ? "quantum: each process's lookahead (the smallest " + rt::formatTime(m.lookahead()) + ")"
                                      : "quantum " + rt::formatTime(m.quantum) + " (lookahead " +
                                            rt::formatTime(m.lookahead()) + ")") +
                  "; watchdog after " + rt::formatTime(m.watchdogSpanOrDefault(scene.objects.size())) +
                  " of simulated time without progress");
}

// A run the watchdog or a signal stopped: its report so far (the VCD is written).
int stopped(const rt::RtsimOptions& o, const nlohmann::json& report, const std::string& why) {
    rt::writeReport(o.report, report);
    if (rt::stopSignal) {  // Ctrl-C or kill: as a shell reports a signal, 128 + its number
        rt::msg::note(rt::msg::kSignal, why);
        return 128 + int(rt::stopSignal);
    }
    rt::msg::error(rt::msg::kWatchdog, "watchdog: " + why);
    return 3;
}

// The frames before the last, the last one, the reference runs, the outputs.
int run(int argc, char** argv, const CLI::App& app, rt::RtsimOptions& o, const std::optional<rt::Rerun>& rerun,
        const rt::Scene& scene, const nlohmann::json& config) {
    const rt::EarlierFrames earlier = rt::runEarlierFrames(argc, argv, o);
    if (earlier.stopped) {
        rt::writeReport(o.report, *earlier.stopped);
        return 3;
    }
    const rt::MachineResult r = rt::runMachine(scene, o.machine);
    nlohmann::json report = rt::machineReport(r, o.machine);
    report["config"] = config;
    report["rerun"] = {{"flags", rt::flagsGiven(app)}, {"version", RTSIM_VERSION}};
    if (rerun) report["rerun"]["of"] = rerun->report["rerun"];  // what it reran
    if (o.frames > 1) rt::listFrames(report, earlier.frames, o.frames);
    if (!r.incomplete.empty()) return stopped(o, report, r.incomplete);
    const double baselineNs = rt::addReferenceRuns(report, argc, argv, o);
    rt::writeOutputs(o, r.image, report);
    if (!o.quiet) rt::printSummary(scene, o, r, report, baselineNs);
    return 0;
}

}  // namespace

int sc_main(int argc, char** argv) {
    CLI::App app{"rtsim: a SystemC model of the sliding-boundary ray-tracing multicomputer (one frame, or a sequence with --frames)"};
    rt::RtsimOptions o;
    o.addTo(app);
    std::optional<rt::Rerun> rerun;  // --rerun REPORT.json: its flags, then those given after (rerun.h)
    rt::Scene scene;
    nlohmann::json config;
    if (Stop s = readCommandLine(app, o, rerun, argc, argv)) return *s;
    if (Stop s = loadScene(o, scene)) return *s;
    if (Stop s = echoConfig(o, scene, rerun, config)) return *s;
    if (Stop s = startBoundaries(o)) return *s;
    sayWhatRuns(o, rerun, scene);
    o.machine.showProgress = !o.quiet && isatty(2);
    try {
        return run(argc, argv, app, o, rerun, scene, config);
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kRun, e.what());
        rt::removeFailedTrace(o.vcd);
        return 1;
    }
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
