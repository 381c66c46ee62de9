// The rtsim command line: flags (each also readable from --config FILE),
// their units and ranges, and the translation into a MachineConfig.
#pragma once
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "config/machine_config.h"
#include "scene_options.h"

namespace rt {

struct RtsimOptions {
    SceneOptions scene;
    MachineConfig machine;
    int mesh = 4;
    std::string meshDims;  // "XxYxZ", overrides --mesh
    std::string image = "rtsim.png", report, vcd, map;
    // --report-detail: auto (full up to kFullReportNodes nodes, summary
    // beyond), full or summary (models/analysis/report.h, ReportDetail).
    std::string reportDetail = "auto";
    static constexpr int kFullReportNodes = 4096;  // 16x16x16
    bool baseline = true;  // also run a 1x1x1 mesh for the speed-up
    bool quiet = false;
    int verbose = 0;  // -v, -vv (tb/messages.h)
    bool asBaseline = false;  // internal: this run is the 1x1x1 baseline of another
    bool asComparison = false;  // internal: this run is the balancing comparison of another
    // Frames (--frames): rendered one after another, each starting with the
    // boundaries where the one before ended; this process runs the last.
    int frames = 1;
    int frameIndex = 0;             // the frame (0-based) this run renders last: frames - 1
    std::vector<double> eyeStep;    // the camera path: the eye moves this much per frame; empty: still
    std::string boundariesFrom;     // a report whose last boundaries this run starts from
    int traceBusiest = 0;           // --trace-nodes busiest[:K]: K (0: not asked)
    // --max-error: the render-time error the user accepts, a fraction (0:
    // not asked; the fidelity is --fidelity's and --quantum's).
    double maxError = 0;

    // The report's detail as --report-detail chooses it for this mesh:
    // whether full, and why ("--report-detail auto: 32768 nodes, more than 4096").
    bool fullReport() const;
    // Whether the frame's policy gathers a sample: sample, from a split of its own (not --boundaries-from's).
    bool gathersSample() const;
    std::string reportDetailWhy() const;

    // Registers every flag on `app`.
    void addTo(CLI::App& app);
    // After parsing: fills `machine` (mesh, size) and validates it; throws
    // CLI::ValidationError naming the flag.
    void finish();
    // The checks of finish() that need no other flag (a --config line's
    // value, checked alone: tb/command_line.h).
    void checkAlone();

private:
    void addMachineParams(CLI::App& app);
    void addSpecial(CLI::App& app, const std::string& name, const char* help, const std::string& group);
    void addPolicyFlag(CLI::App& app, const std::string& group);
    void addOutputFlags(CLI::App& app);
    void addFrameFlags(CLI::App& app);
    void actAsReference();
    void checkSampleLinks() const;
    void readSpecs();
    void setQuantum();

    std::vector<std::string> nodeCostSpecs_, linkSpecs_, traceSpecs_, traceLinkSpecs_;
    std::string traceWindow_;
    bool noGuard_ = false, noBaseline_ = false;
    bool recommended_ = false;  // --balance recommended: the policy is chosen for the mesh in finish()
    std::string rerun_;                 // --rerun: handled before parsing (command_line.h)
    std::vector<std::string> configs_;  // --config: likewise
    std::string quantum_ = "lookahead";  // --quantum: a time, or the lookahead
    std::string maxError_;               // --max-error: "2%" or 0.02
    void setMaxError();
};

}  // namespace rt
