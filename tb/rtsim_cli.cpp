#include "rtsim_cli.h"

#include <filesystem>

#include "json_input.h"
#include "option_parsers.h"
#include "balance/policy.h"

namespace rt {
namespace {
const std::string gm = "Machine", gc = "Costs", gl = "Links", go = "Outputs", gb = "Balancing (sliding boundaries)",
                  gf = "Frames";

// Runs a parser of option_parsers.h, its error reported as CLI11's ("FLAG: what", exit 2).
template <class F>
auto cli(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const OptionError& e) {
        throw CLI::ValidationError(e.flag, e.what());
    }
}

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

void addTime(CLI::App& app, const std::string& flag, Picos& target, const std::string& what, const std::string& group) {
    app.add_option_function<std::string>(flag, [flag, &target](const std::string& s) { target = cli([&] { return parseTimeOf(flag, s); }); }, what)
        ->default_str(formatTime(target))
        ->group(group);
}

// A setting with two named values, kept as whether it is `on`; the value it
// holds now is the default, named first in the error for any other value.
void addChoice(CLI::App& app, const std::string& flag, bool& target, const std::string& on, const std::string& off,
               const std::string& what, const std::string& group) {
    const std::string given = target ? on : off, other = target ? off : on;
    app.add_option_function<std::string>(flag, [flag, &target, on, off, given, other](const std::string& s) {
           if (s != on && s != off) throw CLI::ValidationError(flag, "expected " + given + " or " + other + ", got '" + s + "'");
           target = s == on;
       }, what)
        ->default_str(given)
        ->group(group);
}

}  // namespace

// The flags, group by group, in the order --help lists them (and a
// report's rerun.flags records them).
void RtsimOptions::addTo(CLI::App& app) {
    // A flag given twice (or on the command line and in --config) takes its last value.
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    // The default scene is the paper's experiment on the default 4 x 4 x 4
    // mesh: the spheres crowd into the first 1/N = 1/4 of the progress axis.
    scene.procedural.concentration = 0.25;
    scene.addTo(app, false);
    addMachineFlags(app);
    addCostFlags(app);
    addLinkFlags(app);
    addBalanceFlags(app);
    addOutputFlags(app);
    addFrameFlags(app);
    // (Read before parsing, tb/command_line.h; here for --help.)
    app.add_option("--config", configs_,
                   "read flags from a file: name = value, one per line (repeatable: the files in order, then the "
                   "command line; the last value of a flag wins)");
}

void RtsimOptions::addMachineFlags(CLI::App& app) {
    MachineConfig& m = machine;
    app.add_option("--mesh", mesh, "nodes per axis: an N x N x N mesh (at most 32: 32,768 nodes)")
        ->check(CLI::Range(1, 32))->capture_default_str()->group(gm);
    app.add_option("--mesh-dims", meshDims,
                   "mesh shape XxYxZ instead of --mesh: each 1..64, at most 32,768 nodes (such as 64x64x8); a mesh "
                   "whose grids would not fit in memory is refused with the estimate")
        ->group(gm);
    app.add_option("--max-depth", m.maxDepth, "mirror/refraction levels below the primary ray")
        ->check(CLI::Range(0, 39))->capture_default_str()->group(gm);
}

void RtsimOptions::addCostFlags(CLI::App& app) {
    MachineConfig& m = machine;
    addTime(app, "--cost-sphere", m.costs.test[0], "intersection test, sphere", gc);
    addTime(app, "--cost-polygon", m.costs.test[1], "intersection test, polygon", gc);
    addTime(app, "--cost-cone", m.costs.test[2], "intersection test, cone/cylinder", gc);
    addTime(app, "--cost-voxel", m.costs.voxelStep, "one voxel step of the 3D-DDA", gc);
    addTime(app, "--cost-raygen", m.costs.rayGen, "generating one primary ray", gc);
    addTime(app, "--cost-shade", m.costs.shade, "shading one hit", gc);
    addTime(app, "--cost-send", m.costs.send, "handling one outgoing message", gc);
    addTime(app, "--cost-recv", m.costs.recv, "handling one incoming message", gc);
    addChoice(app, "--hop-handling", m.hopsByLinks, "link", "processor",
              "who pays for a hop: processor (each node's busy time pays --cost-send and --cost-recv per message) or "
              "link (the links' engines do: --cost-send holds the wire before each message, --cost-recv adds to the "
              "latency; the processors pay nothing for a hop)",
              gc);
    addTime(app, "--cost-host", m.hostCost, "frame buffer: accumulating one contribution", gc);
    app.add_option_function<double>("--speed", [&m](double s) {
           if (!(s > 0)) throw CLI::ValidationError("--speed", "must be positive");
           m.speed = s;
       }, "node speed factor (time = cost / speed)")
        ->default_str("1")->group(gc);
    app.add_option_function<std::vector<std::string>>("--node-speed", [&m](const std::vector<std::string>& v) {
           for (const std::string& s : v) {
               const auto [cell, speed] = cli([&] { return parseNodeSpeed(s); });
               m.nodeSpeed[cell] = speed;
           }
       }, "speed factor of one node: x,y,z=SPEED (repeatable)")
        ->group(gc);
    app.add_option("--node-cost", nodeCostSpecs_, "a cost of one node: x,y,z:NAME=TIME, NAME one of sphere polygon cone voxel raygen shade send recv (repeatable)")
        ->group(gc);
}

// The quantum (with the machine's flags), then the links and ports.
void RtsimOptions::addLinkFlags(CLI::App& app) {
    MachineConfig& m = machine;
    app.add_option("--quantum", quantum_,
                   "temporal decoupling: how far a process may run ahead of the kernel. 'lookahead': each process's own, "
                   "the largest that is still exact (its input links' latency plus the smallest message's time on their "
                   "wire); 0: synchronise after every step (also exact, slower); a time: every process by that much, "
                   "exact up to the smallest lookahead, beyond it faster and timing approximate")
        ->capture_default_str()
        ->group(gm);
    addTime(app, "--link-latency", m.link.latency, "link latency", gl);
    app.add_option_function<std::string>("--link-bandwidth", [&m](const std::string& s) { m.link.bandwidth = cli([&] { return parseRateOf("--link-bandwidth", s); }); }, "link bandwidth")
        ->default_str("1GB/s")->group(gl);
    app.add_option("--link-depth", m.link.depth, "messages a link holds before back-pressure")
        ->check(CLI::Range(1, 1000000))->capture_default_str()->group(gl);
    app.add_option("--link-control-depth", m.link.controlDepth,
                   "slots of the links' control lane (load reports, slides, acks ahead of rays); 0: no lane, one FIFO")
        ->check(CLI::Range(0, 1000000))->capture_default_str()->group(gl);
    app.add_option("--link-out-depth", m.link.outDepth,
                   "messages a sender's output buffer holds per link and lane while they wait for a slot; a node whose "
                   "buffer is full blocks (charged as wait, reported as blocked); 0: unbounded, senders never block")
        ->check(CLI::Range(0, 1000000))->capture_default_str()->group(gl);
    addChoice(app, "--link-stats", m.linkDistributions, "full", "counts",
              "what the links keep beyond message counts, bytes, wire, wait and backlog times: full (also latency percentiles, "
              "backlog and buffer high-water marks and the busiest window's utilisation) or counts (not those: a 100 us run "
              "about 7 % faster; timing unchanged)",
              gl);
    app.add_option("--link-set", linkSpecs_, "one link: x,y,z,DIR:latency=T,bandwidth=R,depth=N,control_depth=N,out_depth=N (DIR +x -x +y -y +z -z; any subset; repeatable)")
        ->group(gl);
    app.add_option("--fb-units", m.fbUnits,
                   "frame-buffer units, pixel-interleaved (pixel p in unit p mod K), each with a port from every node; "
                   "1: a single host")
        ->check(CLI::Range(1, 256))->capture_default_str()->group(gl);
    addTime(app, "--fb-latency", m.fbPort.latency, "frame-buffer port latency", gl);
    app.add_option_function<std::string>("--fb-bandwidth", [&m](const std::string& s) { m.fbPort.bandwidth = cli([&] { return parseRateOf("--fb-bandwidth", s); }); }, "frame-buffer port bandwidth")
        ->default_str("1GB/s")->group(gl);
    app.add_option("--fb-depth", m.fbPort.depth, "messages a frame-buffer port holds")->check(CLI::Range(1, 1000000))->capture_default_str()->group(gl);
    app.add_option("--fb-out-depth", m.fbPort.outDepth,
                   "messages a node's output buffer holds per frame-buffer port; a node whose buffer is full blocks; 0: unbounded")
        ->check(CLI::Range(0, 1000000))->capture_default_str()->group(gl);
    app.add_option("--ray-batch", m.rayBatch, "rays per link message (sent when full or before a node waits)")
        ->check(CLI::Range(1, 65536))->capture_default_str()->group(gl);
    app.add_option("--fb-batch", m.fbBatch, "contributions per frame-buffer message")->check(CLI::Range(1, 65536))->capture_default_str()->group(gl);
}

void RtsimOptions::addBalanceFlags(CLI::App& app) {
    BalanceConfig& b = machine.balance;
    // One name each: none (the default) does not balance, recommended is
    // kRecommendedPolicy; `default` meant the latter while being the former.
    const std::string recommended = kRecommendedPolicy;
    std::string policyHelp = "policy: none (the default: no balancing, the boundaries stay where they start); recommended (the recommended policy, " + recommended + ")";
    std::string names = "recommended";
    for (const PolicyInfo& p : policies()) {
        if (std::string(p.name) != "none") policyHelp += std::string("; ") + p.name + " (" + p.help + ")";
        names += std::string(", ") + p.name;
    }
    app.add_option_function<std::string>("--balance", [&b, names, recommended](const std::string& s) {
           if (s == "recommended") b.policy = recommended;
           else if (findPolicy(s)) b.policy = s;
           else if (s == "default")
               throw CLI::ValidationError("--balance", "'default' names no policy: the recommended policy is " + recommended +
                                                           " (or 'recommended'); no balancing is none, the default");
           else throw CLI::ValidationError("--balance", "expected " + names + ", got '" + s + "'");
       }, policyHelp)
        ->default_str("none")->group(gb);
    addTime(app, "--balance-interval", b.interval, "time between load reports", gb);
    app.add_option("--gain", b.gain,
                   "slide: step = gain x load difference x thickness; work: share of the busy-time gap moved; "
                   "quantile: share of the way to the target")
        ->check(CLI::NonNegativeNumber)->default_str("0: the policy's, slide and work 0.25, quantile 0.5")->group(gb);
    app.add_option("--deadband", b.deadband, "no slide while the load difference is at most this")
        ->check(CLI::Range(0.0, 0.999))->capture_default_str()->group(gb);
    app.add_option("--min-thickness", b.minThickness, "guard: a box keeps at least this fraction of its initial thickness")
        ->check(CLI::Range(1e-6, 1.0))->capture_default_str()->group(gb);
    // (Plain flags, not CLI11's negated ones: a report's echo of the flags
    // given (rerun.h) writes a negated flag's stored value, which reads back
    // inverted.)
    app.add_flag("--no-guard", noGuard_,
                 "no guard: slide on loads however old, and whatever the slide costs against the work it moves")
        ->group(gb);
    app.add_option("--max-age", b.maxAge, "guard: no slide on loads older than this many intervals")
        ->check(CLI::Range(0.0, 1e9))->capture_default_str()->group(gb);
    app.add_option("--guard-hop", b.hopRatio,
                   "guard: no slide while a ray's hop to the neighbour (latency + wire) takes longer than this many "
                   "of the giver's mean ray steps")
        ->check(CLI::Range(0.0, 1e9))->capture_default_str()->group(gb);
    app.add_option("--guard-wire", b.wireShare,
                   "guard: no slide across a link that would be busy more than this share of an interval after it: "
                   "the last interval's share plus a ray message per ray step the slab's work took, each by the link's "
                   "narrower limit, its wire or its slots (1: a full link; 0: off)")
        ->check(CLI::Range(0.0, 1e9))->capture_default_str()->group(gb);
    app.add_option("--guard-horizon", b.horizon,
                   "guard: no slide that costs more than the work it moves over this many intervals")
        ->check(CLI::Range(0.0, 1e9))->capture_default_str()->group(gb);
    app.add_option("--report-share", b.reportShare,
                   "load reports on a control lane take at most this share of the link's time: a node reports to a "
                   "neighbour again only once a report's time on the wire divided by this has passed")
        ->check(CLI::Range(1e-6, 1.0))->capture_default_str()->group(gb);
    addChoice(app, "--faces", b.idealLayerFaces, "ideal-layer", "column",
              "column: each column moves its own faces (the machine); ideal-layer: a measuring device, faces shared by a "
              "layer and moved by slide's rule on the layer's summed loads, read without messages (doc/balancing.md)",
              gb);
    app.add_option("--bins", b.bins, "work profile: bins per box thickness along the axis")->check(CLI::Range(1, 4096))->capture_default_str()->group(gb);
    addTime(app, "--cost-rebuild", b.rebuildCost, "updating a node's grid, per object moved in or out", gb);
}

void RtsimOptions::addOutputFlags(CLI::App& app) {
    MachineConfig& m = machine;
    addTime(app, "--watchdog", m.watchdogSpan,
            "stop a run in which no ray, contribution or credit moves for this long in simulated time (exit 3, the "
            "report and VCD so far marked incomplete); 0: the larger of 100 us and 1,000 times the largest cost, "
            "latency or ray wire time",
            go);
    app.add_option("--watchdog-wall", m.watchdogWall, "also stop it after this many seconds of wall-clock time (0: no limit)")
        ->check(CLI::Range(0.0, 1e9))->capture_default_str()->group(go);
    app.add_flag("--fault-drop-credit", m.faultDropFirstCredit, "test only: unit 0 loses the first credit it takes")->group("");
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
    app.add_option("--targets-from", targetsFrom, "internal: resplit's targets for this frame (JSON)")
        ->check(CLI::ExistingFile)->group("");
    app.add_option("--frame-index", frameIndex, "internal: this run is that frame (0-based) of a sequence")
        ->check(CLI::Range(0, 9999))->group("");
    app.add_flag("--as-frame", asFrame, "internal: run as an earlier frame of another run's sequence")->group("");
    app.add_flag("--as-baseline", asBaseline, "internal: run as the 1x1x1 baseline of another run")->group("");
    app.add_flag("--as-comparison", asComparison, "internal: run as the balancing comparison of another run")->group("");
    app.add_flag("--as-first-pass", asFirstPass, "internal: run as the first pass of --trace-nodes busiest")->group("");
}

void RtsimOptions::finish() {
    try {
        if (noGuard_) machine.balance.guard = false;
        if (noBaseline_) baseline = false;
        if (machine.balance.idealLayerFaces && frames > 1)
            throw OptionError("--faces", "ideal-layer measures one frame from faces in line; not with --frames " +
                                             std::to_string(frames));
        machine.dims = {mesh, mesh, mesh};
        if (frameIndex < 0) frameIndex = frames - 1;  // this process renders the last frame of its sequence
        if (asBaseline || asFrame) frames = 1;        // the baseline is of the last frame's view; a frame is one frame
        if (asBaseline || asComparison || asFrame || asFirstPass) actAsReference();
        readSpecs();
        setQuantum();
        machine.balance.axis = scene.axis == "x" ? 0 : scene.axis == "y" ? 1 : 2;  // one progress axis for scene and balancing
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
    } catch (const OptionError& e) {
        throw CLI::ValidationError(e.flag, e.what());
    }
}

// A reference run of another (its 1x1x1 baseline, its balancing
// comparison, an earlier frame of its sequence): no outputs (the caller
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
    }
    // (asComparison: the same machine and frame; the caller sets --balance.)
    // The reference runs' other policy has no faces to share.
    if ((asBaseline || asComparison) && machine.balance.policy != "slide" && machine.balance.policy != "resplit")
        machine.balance.idealLayerFaces = false;
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

}  // namespace rt
