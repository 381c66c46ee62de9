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
// machine itself (models/machine/machine.h), the reference runs
// (reference_runs.h), the outputs (outputs.h) and the summary (summary.h).
#include <malloc.h>
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <systemc>

#include "balance/between_frames.h"
#include "balance/initial_split.h"
#include "balance/sample_end.h"
#include "balance/sample_split.h"
#include "balance/start_links.h"
#include "command_line.h"
#include "config_echo.h"
#include "frame_sequence.h"
#include "frame_state_json.h"
#include "job_memory.h"
#include "json_input.h"
#include "machine/machine.h"
#include "memory_estimate.h"
#include "messages.h"
#include "output_file.h"
#include "outputs.h"
#include "reference_runs.h"
#include "fidelity_choice.h"
#include "analysis/report.h"
#include "rerun.h"
#include "rtsim_cli.h"
#include "scene_error.h"
#include "stops.h"
#include "summary.h"
#include "trace_busiest.h"
#include "utf8.h"
#include "version.h"
#include "wall_clock.h"

// The allocator: jemalloc, told to back the heap with transparent huge
// pages. The model's data is spread over every node (its grid, objects, link
// buffers, stack) and a run visits them in turn, so most of its cost is
// memory access, not arithmetic; 2 MB pages cut the TLB misses and the page
// faults. Freed pages go back to the system over 30 s rather than the
// default 10: a link's backlog grows to tens of megabytes, runs empty and
// grows again, and each time it would find pages given back and the kernel
// would zero fresh ones. (What each bought: doc/history.md, "Figures behind
// the code's comments".) jemalloc reads this at start-up.
extern "C" {
const char* malloc_conf = "thp:always,metadata_thp:always,dirty_decay_ms:30000,muzzy_decay_ms:30000";
}

namespace {

// A step that ends the program returns its exit code; one that lets the
// run go on returns nothing.
using Stop = std::optional<int>;

// The command line, with the flags of its --config files or --rerun report
// before it (command_line.h): parsed and checked.
Stop readCommandLine(CLI::App& app, rt::RtsimOptions& o, rt::CommandLine& cl, int argc, char** argv) {
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
        cl = rt::assembleCommandLine(argc, argv);
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kConfig, e.what());
        return 2;
    }
    try {
        std::vector<std::string> reversed(cl.args.rbegin(), cl.args.rend() - 1);  // (CLI11 takes them reversed, without argv[0])
        app.parse(reversed);
        rt::checkTriples(cl.args, {"--eye", "--look-at", "--eye-step"});
        o.finish();
        rt::msg::install(o.verbose);  // (0 in a reference run)
        rt::setWallLimit(o.machine.watchdogWall);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        rt::msg::error(rt::msg::kConfig, cl.originOf(e.what()) + e.what());
        return 2;
    }
    // The report keeps every flag (its rerun.flags), in JSON, which holds
    // UTF-8 alone: a value of other bytes (a file's name may be any) is
    // refused now, not as the report is written after the run.
    for (size_t i = 1; i < cl.args.size(); ++i) {
        size_t f = i;  // the flag it is given to: itself (--flag=value) or the last flag before it
        while (f > 1 && cl.args[f].rfind("-", 0) != 0) --f;
        const std::string& a = cl.args[f];
        const std::string flag = a.rfind("-", 0) == 0 ? a.substr(0, a.find('=')) : "";
        if (flag.rfind("--", 0) == 0 && rt::isOutputOrInternal(flag.substr(2))) continue;  // (outputs are not kept)
        const std::string value = f == i && a.find('=') != std::string::npos ? a.substr(a.find('=') + 1) : cl.args[i];
        const std::string shown = rt::notUtf8(value);
        if (shown.empty()) continue;
        const std::string msg = (flag.empty() ? "an argument" : flag) + ": " + shown +
                                " is not valid UTF-8 (its bad bytes shown as U+FFFD): the report keeps every flag, in JSON, which cannot hold it";
        rt::msg::error(rt::msg::kConfig, cl.originOf(msg) + msg);
        return 2;
    }
    // The trace flags say what the VCD holds: typed without --vcd, nothing
    // would be traced. (From a --config file or a --rerun report they may
    // wait for a --vcd given later; a reference run's are its parent's.)
    if (o.vcd.empty() && !o.asBaseline && !o.asComparison)
        for (const char* flag : {"trace-nodes", "trace-links", "trace-window"})
            if (cl.given.count(flag)) {
                rt::msg::error(rt::msg::kConfig, std::string("--") + flag +
                                                     ": says what the VCD traces, but no --vcd is given: add --vcd FILE");
                return 2;
            }
    return std::nullopt;
}

// The outputs checked (before the run, not after it), the scene read, the
// image's size checked against the machine's memory.
Stop loadScene(rt::RtsimOptions& o, const rt::CommandLine& cl, rt::Scene& scene, rt::Vec3& firstEye) {
    try {
        rt::checkOutputs(o, cl.inputs(o));
        if (cl.rerun && !cl.givesScene()) rt::checkRerunSceneFile(*cl.rerun, o.scene);  // (before the file is parsed)
        scene = o.scene.load();
        o.scene.imageSize(scene, o.machine.width, o.machine.height);
        if (o.boundariesFrom.empty()) {  // (--start-mix auto, --sample-end auto: by the costs and objects)
            rt::chooseStartMix(o.machine, scene.objects);
            rt::weighStartLinks(o.machine, scene);  // (the camera's view: the half start's long boxes on their links)
            rt::chooseSampleEnd(o.machine, scene);
        }
        o.machine.checkDerivedTimes(scene.objects.size(), o.gathersSample() ? rt::kSampleSumBytes : 0);  // (invalid_argument: exit 2)
        try {
            rt::refuseIfTooBig(o.scene.sizeNamed(o.machine.width, o.machine.height),
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
    } catch (const std::exception& e) {  // --size, --rerun's scene
        rt::msg::error(rt::msg::kConfig, e.what());
        return 2;
    }
    // A frame of a camera path: the eye moved frameIndex steps (the last
    // frame's, or a reference run's of it).
    firstEye = scene.view.from;
    try {
        rt::checkCameraPath(o, scene.view, firstEye);
    } catch (const std::invalid_argument& e) {
        rt::msg::error(rt::msg::kConfig, e.what());
        return 2;
    }
    scene.view.from = rt::eyeOfFrame(o, firstEye, o.frameIndex);
    return std::nullopt;
}

// Every setting as this run uses it (the report's `config`); a rerun
// without flags of its own must arrive at the report's.
Stop echoConfig(const rt::RtsimOptions& o, const rt::Scene& scene, const rt::CommandLine& cl, nlohmann::json& config) {
    try {
        config = rt::configEcho(o, scene);
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kScene, e.what());
        return 2;
    }
    if (!cl.rerun || o.asBaseline || o.asComparison) return std::nullopt;  // (a reference run differs by design)
    const std::string where = "--rerun " + cl.rerun->path + ": ";
    if (cl.rerun->overrides) {  // a what-if: of the report's scene, unless the command line names another
        const std::string differs = cl.givesScene() ? "" : rt::rerunSceneDifference(*cl.rerun, config);
        if (!differs.empty()) {
            rt::msg::error(rt::msg::kConfig, where + "its flags give another scene than its config.scene records: " + differs);
            return 2;
        }
    } else if (const std::string differs = rt::firstDifference(cl.rerun->config, config); !differs.empty()) {
        rt::msg::error(rt::msg::kConfig, where + "this run arrives at other settings than the report's: " + differs +
                                             rt::newerSettingHint(cl.rerun->config, config, cl.rerun->path));
        return 2;
    }
    return std::nullopt;
}

// A run that continues another's boundaries (--boundaries-from): of the
// same scene (where its report says: a file of boundaries alone does not),
// where they ended, and (`resplit`, `measured`) the targets its frame chooses.
Stop startBoundaries(rt::RtsimOptions& o, const rt::Scene& scene) {
    try {
        if (!o.boundariesFrom.empty()) {
            const nlohmann::json report = rt::readJsonFile(o.boundariesFrom, rt::kMaxReportBytes);  // (limits as --rerun's)
            if (report.contains("config") && report["config"].contains("scene")) {
                nlohmann::json there = {{"scene", report["config"]["scene"]}}, here = {{"scene", rt::sceneEcho(o, scene)}};
                if (there["scene"].is_object()) there["scene"].erase("file");  // (the same bytes elsewhere: the same scene)
                here["scene"].erase("file");
                if (const std::string d = rt::firstDifference(there, here); !d.empty())
                    throw std::invalid_argument("its run was of another scene: " + d);
            }
            const rt::FrameState prev = rt::frameStateFromReport(report);
            o.machine.startBoundaries = rt::lastBoundaries(prev, o.machine);
            if (o.machine.balance.betweenFrames()) o.machine.targetBoundaries = rt::resplitTargets(prev, o.machine, &scene.objects);
        }
    } catch (const rt::JsonInputError& e) {  // ("PATH: why")
        rt::msg::error(rt::msg::kConfig, std::string("--boundaries-from ") + e.what());
        return 2;
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kConfig, "--boundaries-from " + o.boundariesFrom + ": " + e.what());
        return 2;
    }
    return std::nullopt;
}

// The job (its frame, the frames before it, its reference runs) must fit
// what the process may use (tb/job_memory.h): refused with the estimate,
// not a bad_alloc.
Stop checkMemory(const rt::RtsimOptions& o, const rt::Scene& scene) {
    try {
        rt::checkJobMemory(o, scene, rt::memoryLimits());
    } catch (const rt::SceneError& e) {
        rt::msg::error(rt::msg::kScene, e.what());
        return 2;
    } catch (const std::exception& e) {  // (start boundaries that do not fit: the run says so)
    }
    return std::nullopt;
}

void sayWhatRuns(const rt::RtsimOptions& o, const std::optional<rt::Rerun>& rerun, const rt::Scene& scene) {
    if (rerun)
        rt::msg::info("running again the flags of a report written by " + rerun->rerun["version"].get<std::string>() +
                      " (this is " RTSIM_VERSION ")" + (rerun->overrides ? ", with the flags given after --rerun on top" : ""));
    const rt::MachineConfig& m = o.machine;
    rt::msg::info((m.lookaheadQuantum ? "quantum: each process's lookahead (the smallest " + rt::formatTime(m.lookahead()) + ")"
                                      : "quantum " + rt::formatTime(m.quantum) + " (lookahead " +
                                            rt::formatTime(m.lookahead()) + ")") +
                  "; watchdog after " + rt::formatTime(m.watchdogSpanOrDefault(scene.objects.size())) +
                  " of simulated time without progress");
    if (!m.balance.startMixWhy.empty())
        rt::msg::info(m.balance.policy + " starts at start mix " + rt::formatNumber(m.balance.startMix) + " (" +
                      m.balance.startMixWhy + ")");
    if (!m.balance.sampleEndWhy.empty())
        rt::msg::info(std::string("sample's gather starts ") +
                      (m.balance.sampleCredit ? "once the frame buffer has its credit back" : "once its rays are generated") +
                      " (" + m.balance.sampleEndWhy + ")");
}

// How a stopped run ends (its report so far written): 3 for the watchdog,
// 128 + N for signal N (as a shell reports one).
int stopped(int code, const std::string& why) {
    if (code == 3) rt::msg::error(rt::msg::kWatchdog, "watchdog: " + why);
    else rt::msg::note(rt::msg::kSignal, why);
    return code;
}

// --max-error: the rung for this scene, mesh and machine, chosen by a
// calibration frame before the echo, which then records it
// (fidelity_choice.h); `fidelity` gets what the report says of it.
Stop chooseRung(rt::RtsimOptions& o, const rt::Scene& scene, rt::FidelityChoice& fidelity) {
    if (o.maxError <= 0) return std::nullopt;
    try {
        fidelity = rt::chooseFidelity(scene, o);
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kRun, std::string("--max-error: the calibration failed: ") + e.what());
        return 1;
    }
    if (rt::stopSignal) return 128 + int(rt::stopSignal);  // (stopped while calibrating: nothing written)
    return std::nullopt;
}

// The reference runs, the outputs and the summary of a finished frame; the
// wall clock's last two parts (the frame was done at `frameDone`).
int finish(const rt::CommandLine& cl, const rt::RtsimOptions& o, const rt::Scene& scene, const rt::MachineResult& r,
           rt::Report& report, rt::RunOutputs& out, rt::WallClock& wall, rt::WallClock::Clock::time_point frameDone) {
    const auto refsFrom = rt::WallClock::now();
    const rt::ReferenceRuns ref = rt::addReferenceRuns(report.json, cl.args, o);
    const auto refsDone = rt::WallClock::now();
    wall.referenceRuns = ref.ran ? rt::secondsBetween(refsFrom, refsDone) : 0;  // (none: the report's assembling)
    const double assembling = rt::secondsBetween(frameDone, refsDone) - wall.referenceRuns;
    out.image(r.image);
    // The report holds the parts up to its own writing; the summary's line
    // holds everything.
    wall.writing = assembling + rt::secondsBetween(refsDone, rt::WallClock::now());
    report.json["wall_clock"] = wall.json();
    out.report(report);
    const bool mapped = out.map(report);
    out.commit();
    wall.writing = assembling + rt::secondsBetween(refsDone, rt::WallClock::now());
    if (rt::stopSignal || ref.stopCode)
        return stopped(rt::stopSignal ? 128 + int(rt::stopSignal) : ref.stopCode,
                       !mapped         ? "the frame is done and written, but for its map: stopped while it was drawn"
                       : ref.stopCode  ? "the frame is done and written; its reference runs were stopped"
                                       : "the frame is done and written; the stop came as it was written");
    if (!o.quiet) rt::printSummary(scene, o, r, report.json, ref.baselineNs, wall);
    return 0;
}

// Every output is written, committed and flushed: the process ends here,
// rather than freeing its results, report and machine piece by piece, which
// the system takes back at once (what that saves at 32x32x32:
// doc/history.md, "At 32x32x32"). Built with AddressSanitizer it returns,
// so that the leak check still sees everything freed.
void endWithoutFreeing(int code) {
#ifndef __SANITIZE_ADDRESS__
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    std::_Exit(code);
#else
    (void)code;
#endif
}

// The frames before the last, the last one, the reference runs, the outputs.
int run(const rt::CommandLine& cl, const CLI::App& app, rt::RtsimOptions& o, const rt::Scene& scene,
        const rt::Vec3& firstEye, const nlohmann::json& config, rt::FidelityChoice& chosenRung, rt::RunOutputs& out) {
    const nlohmann::json& fidelity = chosenRung.json;
    rt::WallClock wall;
    const auto framesFrom = rt::WallClock::now();
    // (The calibration's machine renders the frames: its elaboration is start-up.)
    wall.calibration = fidelity.contains("calibration") ? fidelity["calibration"]["wall_s"].get<double>() : 0.0;
    wall.startUp = rt::secondsBetween(rt::WallClock::processStart(), framesFrom) - wall.calibration;
    rt::EarlierFrames earlier = rt::runEarlierFrames(scene, firstEye, o, std::move(chosenRung.session));
    if (earlier.stopped) {
        out.report(*earlier.stopped);
        out.commit();
        // (The VCD is the last frame's, which had not begun: said, not left out silently.)
        const std::string noVcd = o.vcd.empty() ? "" : "; no VCD written: --vcd traces the sequence's last frame, frame " +
                                                           std::to_string(o.frames) + ", which had not begun";
        return stopped(earlier.exitCode, earlier.why + noVcd);
    }
    std::optional<rt::TraceChoice> chosen;
    if (o.traceBusiest > 0 && !o.vcd.empty()) chosen = rt::traceBusiest(earlier, scene, o);
    o.machine.vcdPath = out.vcdStream();  // (renamed to --vcd at the end)
    o.machine.vcdName = o.vcd;
    const rt::MachineResult r = rt::runLastFrame(earlier, scene, o.machine);
    if (!o.vcd.empty() && r.incomplete.empty() && o.machine.traceFrom > r.renderTime)  // (a valid VCD, of nothing)
        rt::msg::warning(rt::msg::kOutput, "--trace-window: starts at " + rt::formatTime(o.machine.traceFrom) +
                                               ", after the frame ended at " + rt::formatTime(r.renderTime) +
                                               ": the VCD holds its declarations alone");
    const auto frameDone = rt::WallClock::now();
    wall.startUp += earlier.elaborationSeconds;  // building the machine (once, for every frame)
    wall.frames = rt::secondsBetween(framesFrom, frameDone) - earlier.elaborationSeconds;
    const rt::OrderlyStops orderly;  // from here on a stop still writes the frame's outputs
    rt::Report report = rt::frameReport(r, o.machine, o);
    nlohmann::json& j = report.json;
    j["config"] = config;
    j["rerun"] = {{"flags", rt::flagsGiven(app)}, {"version", RTSIM_VERSION}};
    if (cl.rerun) j["rerun"]["of"] = cl.rerun->rerun;  // what it reran (its flags and version)
    if (o.frames > 1) rt::listFrames(j, earlier.frames, o.frames, r.frameStart - earlier.origin);
    if (chosen) j["trace_busiest"] = rt::traceChoiceJson(o.traceBusiest, *chosen);
    if (!fidelity.is_null()) j["fidelity"] = fidelity;
    out.gtkw(r.gtkw);
    if (!r.incomplete.empty()) {  // the watchdog or a signal: the report and VCD so far
        out.report(report);
        out.commit();
        return stopped(rt::stopSignal ? 128 + int(rt::stopSignal) : 3, r.incomplete);
    }
    const int code = finish(cl, o, scene, r, report, out, wall, frameDone);
    endWithoutFreeing(code);
    return code;
}

}  // namespace

int sc_main(int argc, char** argv) {
    // Freed memory stays with the process, for the next allocation to reuse:
    // by default glibc hands large blocks back to the system and takes
    // fresh, zeroed pages for the next, which was half of a 32x32x32 mesh's
    // start-up (every node's and link's buffers are allocated then).
    mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
    mallopt(M_MMAP_THRESHOLD, 32 << 20);  // (glibc's largest)
    CLI::App app{"rtsim: a SystemC model of the sliding-boundary ray-tracing multicomputer (one frame, or a sequence with --frames)",
                 "rtsim"};
    rt::RtsimOptions o;
    o.addTo(app);
    rt::CommandLine cl;  // the flags of --config files or a --rerun report, then the command line's
    rt::Scene scene;
    rt::Vec3 firstEye;  // frame 1's (--eye-step moves it each frame)
    nlohmann::json config;
    rt::FidelityChoice fidelity;  // --max-error: the rung chosen, how, and the machine that calibrated it
    if (Stop s = readCommandLine(app, o, cl, argc, argv)) return *s;
    if (Stop s = loadScene(o, cl, scene, firstEye)) return *s;
    if (Stop s = startBoundaries(o, scene)) return *s;
    if (Stop s = checkMemory(o, scene)) return *s;
    if (Stop s = chooseRung(o, scene, fidelity)) return *s;
    if (Stop s = echoConfig(o, scene, cl, config)) return *s;
    sayWhatRuns(o, cl.rerun, scene);
    o.machine.showProgress = !o.quiet && isatty(2);
    rt::RunOutputs out(o);  // each to a temporary file until the end (outputs.h)
    try {
        return run(cl, app, o, scene, firstEye, config, fidelity, out);
    } catch (const rt::SplitError& e) {  // (checked as the machine is built: bad input, exit 2)
        const std::string from = o.boundariesFrom.empty() ? "" : "--boundaries-from " + o.boundariesFrom + ": ";
        char thick[64];
        std::snprintf(thick, sizeof thick, " (--min-thickness %g here)", o.machine.balance.minThickness);
        rt::msg::error(rt::msg::kConfig, from + e.what() + thick);
        return 2;
    } catch (const std::exception& e) {
        rt::msg::error(rt::msg::kRun, e.what());
        return 1;  // (nothing committed; `out` removes its temporaries)
    }
}

int main(int argc, char** argv) {
    setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 0);
    // A child run (a reference run) says so in its messages (it shares its
    // parent's stderr)...
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--as-baseline") rt::msg::setProgram("rtsim (its baseline run)");
        if (a == "--as-comparison") rt::msg::setProgram("rtsim (its comparison run)");
    }
    // Ctrl-C, SIGTERM and --watchdog-wall wherever rtsim is (stops.h).
    rt::installStopHandlers();
    // ...and ends with its parent.
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--as-baseline" || a == "--as-comparison") {
            prctl(PR_SET_PDEATHSIG, SIGTERM);
            if (getppid() == 1) return 128 + SIGTERM;  // (it died before that)
            break;
        }
    }
    // A SystemC warning is a failed run, not a line to scroll past.
    sc_core::sc_report_handler::set_actions(sc_core::SC_WARNING, sc_core::SC_DISPLAY | sc_core::SC_THROW);
    // The host ends the frame with sc_stop(); that is not news.
    sc_core::sc_report_handler::set_actions("/OSCI/SystemC", sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
    return sc_core::sc_elab_and_sim(argc, argv);
}
