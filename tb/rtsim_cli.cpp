#include "rtsim_cli.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "json_input.h"
#include "option_parsers.h"
#include "param_flags.h"
#include "balance/policy.h"

namespace rt {
namespace {
const std::string go = "Outputs", gf = "Frames";

// A regular file of at most `limit` bytes: files read whole (a fifo or
// /dev/urandom would never end).
CLI::Validator regularFileAtMost(uintmax_t limit) {
    return CLI::Validator(
        [limit](std::string& path) {
            std::error_code ec;
            if (!std::filesystem::is_regular_file(path, ec)) return "not a regular file: '" + path + "'";
            const auto size = std::filesystem::file_size(path, ec);
            if (ec || size > limit) return "'" + path + "' is larger than " + std::to_string(limit) + " bytes";
            return std::string();
        },
        "", "");
}

}  // namespace

// The flags, group by group, in the order --help lists them (and a
// report's rerun.flags records them).
void RtsimOptions::addTo(CLI::App& app) {
    // A flag given twice (or on the command line and in --config) takes its last value.
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    scene.procedural.concentration = kDefaultConcentration;  // (the paper's experiment on the default mesh)
    scene.addTo(app, false);
    addMachineParams(app);
    addOutputFlags(app);
    addFrameFlags(app);
    // (Read before parsing, tb/command_line.h; here for --help.)
    app.add_option("--config", configs_,
                   "read flags from a file: name = value, one per line (repeatable: the files in order, then the "
                   "command line; the last value of a flag wins)")
        ->expected(1);  // (one file a --config: the help shows no list)
    decimalNumbersOnly(app);
}

// The machine's parameters, from their tables (config/machine_config.h,
// channel/link_params.h), in the tables' order.
void RtsimOptions::addMachineParams(CLI::App& app) {
    MachineConfig& m = machine;
    for (const Param<MachineConfig>& p : machineParams()) {
        const std::string group = p.group;
        if (p.kind == ParamKind::Special) {
            addSpecial(app, p.name, p.help, group);
        } else if (p.kind != ParamKind::Part) {
            addParam(app, p, m, std::string("--") + p.name, p.help, group);
        } else if (p.part == std::string("costs")) {
            for (const Param<Costs>& c : costParams()) addParam(app, c, m.costs, std::string("--cost-") + c.name, c.help, group);
        } else if (p.part == std::string("link") || p.part == std::string("fb-port")) {
            const bool port = p.part == std::string("fb-port");
            for (const Param<LinkParams>& l : linkParams())
                if (!port || l.portHelp)
                    addParam(app, l, port ? m.fbPort : m.link, std::string(port ? "--fb-" : "--link-") + l.name,
                             port ? l.portHelp : l.help, group);
        } else {
            for (const Param<BalanceConfig>& b : balanceParams()) {
                if (b.kind == ParamKind::Special) addSpecial(app, b.name, b.help, group);
                else addParam(app, b, m.balance, std::string("--") + b.name, b.help, group);
            }
        }
    }
}

// The rows of kind Special: flags with a syntax of their own.
void RtsimOptions::addSpecial(CLI::App& app, const std::string& name, const char* help, const std::string& group) {
    MachineConfig& m = machine;
    const std::string flag = "--" + name;
    if (name == "mesh") {
        app.add_option(flag, mesh, help)->check(CLI::Range(1, 32))->capture_default_str()->group(group);
    } else if (name == "mesh-dims") {
        app.add_option(flag, meshDims, help)->group(group);
    } else if (name == "node-speed") {
        app.add_option_function<std::vector<std::string>>(flag, [&m](const std::vector<std::string>& v) {
               for (const std::string& s : v) {
                   const auto [cell, speed] = cli([&] { return parseNodeSpeed(s); });
                   m.nodeSpeed[cell] = speed;
               }
           }, help)
            ->group(group);
    } else if (name == "node-cost") {
        std::string names;
        for (const Param<Costs>& c : costParams()) names += std::string(names.empty() ? "" : " ") + c.name;
        app.add_option(flag, nodeCostSpecs_, "a cost of one node: x,y,z:NAME=TIME, NAME one of " + names + " (repeatable)")->group(group);
    } else if (name == "quantum") {
        app.add_option(flag, quantum_, help)->capture_default_str()->group(group);
    } else if (name == "max-error") {
        app.add_option(flag, maxError_, help)->group(group);
    } else if (name == "link-set") {
        std::string keys;
        for (const Param<LinkParams>& l : linkParams())
            keys += std::string(keys.empty() ? "" : ",") + linkSetKey(l.name) + "=" +
                    (l.kind == ParamKind::Time ? "T" : l.kind == ParamKind::Rate ? "R" : "N");
        app.add_option(flag, linkSpecs_, "one link: x,y,z,DIR:" + keys + " (DIR +x -x +y -y +z -z; any subset; repeatable)")->group(group);
    } else if (name == "balance") {
        addPolicyFlag(app, group);
    } else if (name == "no-guard") {
        // (Plain flags, not CLI11's negated ones: a report's echo of the flags
        // given (rerun.h) writes a negated flag's stored value, which reads back
        // inverted.)
        app.add_flag(flag, noGuard_, help)->group(group);
    } else if (name == "fault-drop-credit") {
        app.add_flag(flag, m.faultDropFirstCredit, help)->group(group);
    } else {
        throw std::logic_error("parameter " + flag + ": no reader for it");
    }
}

// --balance: a policy by name (config/policy_table.h).
void RtsimOptions::addPolicyFlag(CLI::App& app, const std::string& group) {
    BalanceConfig& b = machine.balance;
    // One name each: none (the default) does not balance, recommended is
    // recommendedPolicy's choice for the mesh (finish(), once the mesh and
    // the axis are known); `default` meant the latter while being the former.
    const std::string recommended = "sample on columns of 2 to " + std::to_string(kLongestColumnSampled) +
                                    " boxes, measured on longer ones, none on columns of one box";
    std::string policyHelp = "policy: none (the default: no balancing, the boundaries stay where they start); recommended (the recommended policy: " + recommended + ")";
    std::string names = "recommended";
    for (const PolicyInfo& p : policies()) {
        if (std::string(p.name) != "none") policyHelp += std::string("; ") + p.name + " (" + p.help + ")";
        names += std::string(", ") + p.name;
    }
    app.add_option_function<std::string>("--balance", [this, &b, names, recommended](const std::string& s) {
           recommended_ = s == "recommended";
           if (recommended_) b.policy = "none";  // (chosen in finish())
           else if (findPolicy(s)) b.policy = s;
           else if (s == "default")
               throw CLI::ValidationError("--balance", "'default' names no policy: the recommended policy is " + recommended +
                                                           " (or 'recommended'); no balancing is none, the default");
           else throw CLI::ValidationError("--balance", "expected " + names + ", got '" + s + "'");
       }, policyHelp)
        ->default_str("none")->group(group);
}

void RtsimOptions::addOutputFlags(CLI::App& app) {
    app.add_option("--image", image, "output PNG")->capture_default_str()->group(go);
    app.add_option("--report", report, "JSON report (with the flags given: --rerun runs it again)")->group(go);
    // (Read before parsing, tb/rerun.h; here for --help.)
    app.add_option("--rerun", rerun_, "run a report's run again: its flags, then any given after it (a what-if); "
                                      "without any, checks that it arrives at the report's settings")
        ->group(go);
    app.add_option("--map", map, "a picture of the mesh for this run (PNG: loads, link utilisation, boundaries; "
                                 "scripts/mesh_map.py, with Debian's python3-matplotlib)")
        ->group(go);
    app.add_option("--report-detail", reportDetail,
                   "how much of each node and link the report keeps: full; summary (without a link's settings, counts by "
                   "message type, latencies and high-water marks, and a node's balancing intervals; written without "
                   "indentation: a 32x32x32 mesh's report at 64x64: 340 MB -> 69 MB); auto: full up to 4096 nodes, summary beyond")
        ->check(CLI::IsMember({"auto", "full", "summary"}))->capture_default_str()->group(go);
    app.add_option("--vcd", vcd, "VCD waveform (a .gtkw save file is written beside it)")->group(go);
    app.add_option("--trace-nodes", traceSpecs_,
                   "nodes to trace in the VCD: x,y,z (repeatable; default all), or busiest[:K]: the K (default 4) busiest "
                   "nodes and the K links busy longest with a backlog, chosen by a first pass of the same run without "
                   "waveforms (the run takes twice as long)")
        ->group(go);
    app.add_option("--trace-links", traceLinkSpecs_,
                   "links to trace in the VCD besides the traced nodes' own: x,y,z (all of the node's), x,y,z,DIR "
                   "(DIR +x -x +y -y +z -z) or x,y,z,fb (its frame-buffer port) (repeatable)")
        ->group(go);
    app.add_option("--trace-window", traceWindow_, "time window of the VCD: FROM,TO (e.g. 0,50us)")->group(go);
    app.add_flag("--no-baseline", noBaseline_,
                 "skip the reference runs: the 1x1x1 mesh that gives the speed-up, and the same frame with the recommended "
                 "policy (or, when balancing, without) that gives the balancing ratio")
        ->group(go);
    app.add_flag("-q,--quiet", quiet, "no summary")->group(go);
    app.add_flag("-v,--verbose", verbose,
                 "say more on stderr: -v what rtsim does and each message's SystemC report ID (rtsim/config, "
                 "rtsim/scene, ...); -vv also SystemC's own information")
        ->group(go);
}

void RtsimOptions::addFrameFlags(CLI::App& app) {
    app.add_option("--frames", frames,
                   "frames rendered one after another, each starting with the boundaries where the one before ended, "
                   "as a running machine would; the outputs and the summary are the last frame's, the report lists "
                   "every frame's render time")
        ->check(CLI::Range(1, 10000))->capture_default_str()->group(gf);
    app.add_option("--eye-step", eyeStep, "camera path: the eye moves by x y z (or x,y,z) each frame; the point looked at stays")
        ->expected(3)->delimiter(',')->check(finiteNumber())->group(gf);
    app.add_option("--boundaries-from", boundariesFrom,
                   "start each column's boundaries where they ended in this report's run (the same scene, mesh and axis)")
        ->check(regularFileAtMost(kMaxReportBytes))->group(gf);
    app.add_flag("--as-baseline", asBaseline, "internal: run as the 1x1x1 baseline of another run")->group("");
    app.add_flag("--as-comparison", asComparison, "internal: run as the balancing comparison of another run")->group("");
}

void RtsimOptions::finish() {
    try {
        if (noGuard_) machine.balance.guard = false;
        if (noBaseline_) baseline = false;
        if (!eyeStep.empty() && eyeStep.size() != 3) throw OptionError("--eye-step", "expected three numbers x y z");
        if (machine.balance.idealLayerFaces && frames > 1)
            throw OptionError("--faces", "ideal-layer measures one frame from faces in line; not with --frames " +
                                             std::to_string(frames));
        if (machine.balance.startMix != kStartMixAuto && !boundariesFrom.empty())
            throw OptionError("--start-mix", "the frame starts where --boundaries-from's run left its boundaries, not at a "
                                             "split of its own");
        if (machine.balance.sampleCredit && !boundariesFrom.empty())
            throw OptionError("--sample-end", "the frame starts where --boundaries-from's run left its boundaries: "
                                              "sample gathers no sample to end");
        machine.dims = {mesh, mesh, mesh};
        machine.balance.axis = scene.axis == "x" ? 0 : scene.axis == "y" ? 1 : 2;  // one progress axis for scene and balancing
        if (recommended_) {  // (before a reference run's settings, which depend on the policy)
            PolicyChoice c = recommendedPolicy(meshDims.empty() ? machine.dims : parseMeshDims(meshDims), machine.balance.axis);
            machine.balance.policy = c.policy;
            machine.balance.recommendedWhy = std::move(c.why);
        }
        if (!asBaseline && !asComparison) checkSampleLinks();
        // (given, not auto: a policy that holds no planes between frames has none to polish; a
        // reference run, which does not balance or balances the other way, takes the run's flags)
        if (machine.balance.polishTries > 0 && !machine.balance.betweenFrames() && !asBaseline && !asComparison)
            throw OptionError("--polish-tries", "only resplit, measured and sample polish the planes they hold between "
                                                "frames, not " + machine.balance.named());
        if (machine.balance.polishTries == kPolishTriesAuto)
            machine.balance.polishTries = machine.balance.policy == "sample" ? kSamplePolishTries : 0;
        frameIndex = frames - 1;     // this process renders the last frame of its sequence last
        if (asBaseline) frames = 1;  // the baseline is of the last frame's view
        if (asBaseline || asComparison) actAsReference();
        readSpecs();
        setQuantum();
        setMaxError();
    } catch (const OptionError& e) {
        throw CLI::ValidationError(e.flag, e.what());
    }
    try {
        machine.validate();
    } catch (const std::invalid_argument& e) {
        const std::string msg = e.what();
        const size_t colon = msg.find(':');
        throw CLI::ValidationError(msg.substr(0, colon), msg.substr(colon + 2));
    }
}

bool RtsimOptions::gathersSample() const { return machine.balance.policy == "sample" && boundariesFrom.empty(); }

// --sample-links on acts only where sample gathers a sample, on columns of
// at most kLongestColumnSampled boxes: elsewhere it is refused.
void RtsimOptions::checkSampleLinks() const {
    const BalanceConfig& b = machine.balance;
    if (!b.sampleLinks) return;
    if (b.policy != "sample") throw OptionError("--sample-links on", onlySampleGathers(b.named()));
    if (!gathersSample())
        throw OptionError("--sample-links on", "the frame starts where --boundaries-from's run left its boundaries: sample gathers no sample");
    const int column = (meshDims.empty() ? machine.dims : parseMeshDims(meshDims))[size_t(b.axis)];
    if (column > kLongestColumnSampled)
        throw OptionError("--sample-links on", "acts on columns of at most " + std::to_string(kLongestColumnSampled) +
                                                   " boxes, these have " + std::to_string(column));
}

bool RtsimOptions::fullReport() const {
    return reportDetail == "full" || (reportDetail == "auto" && machine.nodeCount() <= kFullReportNodes);
}

std::string RtsimOptions::reportDetailWhy() const {
    if (reportDetail != "auto") return "--report-detail " + reportDetail;
    return "--report-detail auto: " + std::to_string(machine.nodeCount()) + " nodes, " +
           (fullReport() ? "at most " : "more than ") + std::to_string(kFullReportNodes);
}

void RtsimOptions::checkAlone() {
    try {
        readSpecs();
        setQuantum();
        setMaxError();
    } catch (const OptionError& e) {
        throw CLI::ValidationError(e.flag, e.what());
    }
}

// A reference run of another (its 1x1x1 baseline, its balancing
// comparison): no outputs (the caller
// reads its report), and the baseline is one node with the global costs.
void RtsimOptions::actAsReference() {
    traceSpecs_.clear();
    traceWindow_.clear();
    vcd.clear();
    map.clear();
    image.clear();
    baseline = false;
    quiet = true;
    verbose = 0;  // (the parent says what it does)
    if (asBaseline) {  // one node with the global costs: no per-node or per-link settings
        meshDims = "1x1x1";
        nodeCostSpecs_.clear();
        linkSpecs_.clear();
        machine.nodeSpeed.clear();
        machine.balance.policy = "none";  // one node has no boundary to slide
        boundariesFrom.clear();           // nor one to start at (a mesh's report does not fit it)
    }
    // (asComparison: the same machine and frame; the caller sets --balance.)
    // The reference runs' other policy has no faces to share.
    if ((asBaseline || asComparison) && machine.balance.policy != "slide" && machine.balance.policy != "resplit")
        machine.balance.idealLayerFaces = false;
    if ((asBaseline || asComparison) && !machine.balance.startsAtObjects()) machine.balance.startMix = kStartMixAuto;  // (its start is uniform)
    if ((asBaseline || asComparison) && machine.balance.policy != "sample")
        machine.balance.sampleCredit = machine.balance.sampleLinks = false;  // (no sample)
    // A reference run is timed as its run asks, without a calibration of its own; express only where it applies.
    maxError_.clear();
    if (!machine.balance.boxesStayPut()) machine.express = machine.through = false;
}

// The flags whose values have a syntax of their own (option_parsers.h).
void RtsimOptions::readSpecs() {
    MachineConfig& m = machine;
    if (!meshDims.empty()) m.dims = parseMeshDims(meshDims);
    for (const std::string& s : nodeCostSpecs_) applyNodeCost(s, m.costs, m.nodeCosts);
    for (const std::string& s : linkSpecs_) {
        const auto [where, params] = parseLinkSet(s, m.link);
        m.linkOverride[where] = params;
    }
    for (const std::string& s : traceSpecs_) {
        if (s.rfind("busiest", 0) == 0) {
            traceBusiest = parseBusiest(s);
            if (traceSpecs_.size() > 1) throw OptionError("--trace-nodes", "busiest chooses the nodes itself: not with x,y,z");
        } else {
            m.traceNodes.push_back(parseCell("--trace-nodes", s));
        }
    }
    for (const std::string& s : traceLinkSpecs_) m.traceLinks.push_back(parseTraceLink(s));
    if (!traceWindow_.empty()) std::tie(m.traceFrom, m.traceTo) = parseTraceWindow(traceWindow_);
    m.vcdPath = vcd;
}

// After every link and balancing setting: each process's lookahead depends
// on its links and on the smallest message they carry.
void RtsimOptions::setQuantum() {
    MachineConfig& m = machine;
    m.lookaheadQuantum = quantum_ == "lookahead";
    if (m.lookaheadQuantum) {
        m.quantum = m.lookahead();
        return;
    }
    const auto q = parseTime(quantum_);
    if (!q)
        throw OptionError("--quantum", "expected 'lookahead' or a non-negative time with a unit (ps ns us ms s), got '" +
                                           quantum_ + "'");
    m.quantum = *q;
}

// --max-error: rtsim picks the rung (fidelity_choice.h), so not with a rung given.
void RtsimOptions::setMaxError() {
    maxError = maxError_.empty() ? 0 : parseErrorShare(maxError_);
    if (maxError > 0 && (quantum_ != "lookahead" || machine.usesRelay()))  // (--quantum lookahead is the exact rung's own)
        throw OptionError("--max-error", "it picks --fidelity and --quantum itself: not with " +
                                             (machine.usesRelay() ? std::string("--fidelity ") + machine.relayRung()
                                                                  : "--quantum " + quantum_));
}

}  // namespace rt
