#include "rtsim_cli.h"

#include "policy.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

namespace rt {
namespace {
// A --config file is a few dozen lines; a report, with the per-interval
// history bounded, a few MB.
constexpr uintmax_t kMaxConfigBytes = 1 << 20, kMaxReportBytes = uintmax_t(1) << 30;

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

// "x,y,z" node coordinates.
Cell parseCell(const std::string& flag, const std::string& s) {
    Cell c{};
    char comma1 = 0, comma2 = 0;
    std::istringstream in(s);
    if (!(in >> c[0] >> comma1 >> c[1] >> comma2 >> c[2]) || comma1 != ',' || comma2 != ',' || !in.eof())
        throw CLI::ValidationError(flag, "expected node coordinates x,y,z, got '" + s + "'");
    return c;
}

Picos timeOf(const std::string& flag, const std::string& s) {
    const auto t = parseTime(s);
    if (!t)
        throw CLI::ValidationError(flag, "expected a non-negative time with a unit (ps ns us ms s), at most 1000 s, got '" + s + "'");
    return *t;
}

double rateOf(const std::string& flag, const std::string& s) {
    const auto r = parseRate(s);
    if (!r) throw CLI::ValidationError(flag, "expected a positive rate with a unit (B/s KB/s MB/s GB/s, b/s .. Gb/s), got '" + s + "'");
    return *r;
}

void addTime(CLI::App& app, const std::string& flag, Picos& target, const std::string& what, const std::string& group) {
    app.add_option_function<std::string>(flag, [flag, &target](const std::string& s) { target = timeOf(flag, s); }, what)
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

// Cost names used by --node-cost.
Picos* costField(Costs& c, const std::string& name) {
    if (name == "sphere") return &c.test[0];
    if (name == "polygon") return &c.test[1];
    if (name == "cone") return &c.test[2];
    if (name == "voxel") return &c.voxelStep;
    if (name == "raygen") return &c.rayGen;
    if (name == "shade") return &c.shade;
    if (name == "send") return &c.send;
    if (name == "recv") return &c.recv;
    return nullptr;
}

}  // namespace

void RtsimOptions::addTo(CLI::App& app) {
    // A flag given twice (or on the command line and in --config) takes its last value.
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    // The default scene is the paper's experiment on the default 4 x 4 x 4
    // mesh: the spheres crowd into the first 1/N = 1/4 of the progress axis.
    scene.procedural.concentration = 0.25;
    scene.addTo(app, false);
    MachineConfig& m = machine;
    const std::string gm = "Machine", gc = "Costs", gl = "Links", go = "Outputs";
    app.add_option("--mesh", mesh, "nodes per axis: an N x N x N mesh")->check(CLI::Range(1, 16))->capture_default_str()->group(gm);
    app.add_option("--mesh-dims", meshDims, "mesh shape XxYxZ (each 1..16), instead of --mesh")->group(gm);
    app.add_option("--max-depth", m.maxDepth, "mirror/refraction levels below the primary ray")
        ->check(CLI::Range(0, 39))->capture_default_str()->group(gm);

    addTime(app, "--cost-sphere", m.costs.test[0], "intersection test, sphere", gc);
    addTime(app, "--cost-polygon", m.costs.test[1], "intersection test, polygon", gc);
    addTime(app, "--cost-cone", m.costs.test[2], "intersection test, cone/cylinder", gc);
    addTime(app, "--cost-voxel", m.costs.voxelStep, "one voxel step of the 3D-DDA", gc);
    addTime(app, "--cost-raygen", m.costs.rayGen, "generating one primary ray", gc);
    addTime(app, "--cost-shade", m.costs.shade, "shading one hit", gc);
    addTime(app, "--cost-send", m.costs.send, "handling one outgoing message", gc);
    addTime(app, "--cost-recv", m.costs.recv, "handling one incoming message", gc);
    addTime(app, "--cost-host", m.hostCost, "frame buffer: accumulating one contribution", gc);
    app.add_option_function<double>("--speed", [&m](double s) {
           if (!(s > 0)) throw CLI::ValidationError("--speed", "must be positive");
           m.speed = s;
       }, "node speed factor (time = cost / speed)")
        ->default_str("1")->group(gc);
    app.add_option_function<std::vector<std::string>>("--node-speed", [&m](const std::vector<std::string>& v) {
           for (const std::string& s : v) {
               const size_t eq = s.find('=');
               if (eq == std::string::npos) throw CLI::ValidationError("--node-speed", "expected x,y,z=SPEED, got '" + s + "'");
               double sp;
               std::istringstream in(s.substr(eq + 1));
               if (!(in >> sp) || !in.eof() || !(sp > 0)) throw CLI::ValidationError("--node-speed", "speed must be a positive number in '" + s + "'");
               m.nodeSpeed[parseCell("--node-speed", s.substr(0, eq))] = sp;
           }
       }, "speed factor of one node: x,y,z=SPEED (repeatable)")
        ->group(gc);
    app.add_option("--node-cost", nodeCostSpecs_, "a cost of one node: x,y,z:NAME=TIME, NAME one of sphere polygon cone voxel raygen shade send recv (repeatable)")
        ->group(gc);

    app.add_option("--quantum", quantum_,
                   "temporal decoupling: how far a process may run ahead of the kernel. 'lookahead': each process's own, "
                   "the largest that is still exact (its input links' latency plus the smallest message's time on their "
                   "wire); 0: synchronise after every step (also exact, slower); a time: every process by that much, "
                   "exact up to the smallest lookahead, beyond it faster and timing approximate")
        ->capture_default_str()
        ->group(gm);
    addTime(app, "--link-latency", m.link.latency, "link latency", gl);
    app.add_option_function<std::string>("--link-bandwidth", [&m](const std::string& s) { m.link.bandwidth = rateOf("--link-bandwidth", s); }, "link bandwidth")
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
              "what the links keep beyond message counts, bytes, wire and wait times: full (also latency percentiles and "
              "backlog and buffer high-water marks) or counts (not those: a 100 us run about 7 % faster; timing unchanged)",
              gl);
    app.add_option("--link-set", linkSpecs_, "one link: x,y,z,DIR:latency=T,bandwidth=R,depth=N,control_depth=N,out_depth=N (DIR +x -x +y -y +z -z; any subset; repeatable)")
        ->group(gl);
    app.add_option("--fb-units", m.fbUnits,
                   "frame-buffer units, pixel-interleaved (pixel p in unit p mod K), each with a port from every node; "
                   "1: a single host")
        ->check(CLI::Range(1, 256))->capture_default_str()->group(gl);
    addTime(app, "--fb-latency", m.fbPort.latency, "frame-buffer port latency", gl);
    app.add_option_function<std::string>("--fb-bandwidth", [&m](const std::string& s) { m.fbPort.bandwidth = rateOf("--fb-bandwidth", s); }, "frame-buffer port bandwidth")
        ->default_str("1GB/s")->group(gl);
    app.add_option("--fb-depth", m.fbPort.depth, "messages a frame-buffer port holds")->check(CLI::Range(1, 1000000))->capture_default_str()->group(gl);
    app.add_option("--fb-out-depth", m.fbPort.outDepth,
                   "messages a node's output buffer holds per frame-buffer port; a node whose buffer is full blocks; 0: unbounded")
        ->check(CLI::Range(0, 1000000))->capture_default_str()->group(gl);
    app.add_option("--ray-batch", m.rayBatch, "rays per link message (sent when full or before a node waits)")
        ->check(CLI::Range(1, 65536))->capture_default_str()->group(gl);
    app.add_option("--fb-batch", m.fbBatch, "contributions per frame-buffer message")->check(CLI::Range(1, 65536))->capture_default_str()->group(gl);

    const std::string gb = "Balancing (sliding boundaries)";
    BalanceConfig& b = m.balance;
    std::string policyHelp = "policy: default (the recommended one: " + std::string(kDefaultPolicy) + ")";
    std::string names = "default";
    for (const PolicyInfo& p : policies()) {
        policyHelp += std::string("; ") + p.name + " (" + p.help + ")";
        names += std::string(", ") + p.name;
    }
    app.add_option_function<std::string>("--balance", [&b, names](const std::string& s) {
           if (s == "default") b.policy = kDefaultPolicy;
           else if (findPolicy(s)) b.policy = s;
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
    app.add_option("--vcd", vcd, "VCD waveform (a .gtkw save file is written beside it)")->group(go);
    app.add_option("--trace-nodes", traceSpecs_, "nodes to trace in the VCD: x,y,z (repeatable; default all)")->group(go);
    app.add_option("--trace-links", traceLinkSpecs_,
                   "links to trace in the VCD besides the traced nodes' own: x,y,z (all of the node's), x,y,z,DIR "
                   "(DIR +x -x +y -y +z -z) or x,y,z,fb (its frame-buffer port) (repeatable)")
        ->group(go);
    app.add_option("--trace-window", traceWindow_, "time window of the VCD: FROM,TO (e.g. 0,50us)")->group(go);
    app.add_flag("--no-baseline", noBaseline_,
                 "skip the reference runs: the 1x1x1 mesh that gives the speed-up, and the same frame with the default "
                 "balancing (or, when balancing, without) that gives the balancing ratio")
        ->group(go);
    app.add_flag("-q,--quiet", quiet, "no summary")->group(go);
    app.add_flag("-v,--verbose", verbose,
                 "say more on stderr: -v what rtsim does and each message's SystemC report ID (rtsim/config, "
                 "rtsim/scene, ...); -vv also SystemC's own information")
        ->group(go);
    const std::string gf = "Frames";
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
    // A regular file of bounded size: CLI11 reads it whole, so /dev/urandom
    // or a fifo would never end.
    app.set_config("--config", "", "read flags from a file (INI/TOML: name = value, one per line)")
        ->check(regularFileAtMost(kMaxConfigBytes));
    app.allow_config_extras(CLI::config_extras_mode::error);  // a misspelt name is an error, not ignored
}

void RtsimOptions::finish() {
    MachineConfig& m = machine;
    if (noGuard_) m.balance.guard = false;
    if (noBaseline_) baseline = false;
    if (m.balance.idealLayerFaces && frames > 1)
        throw CLI::ValidationError("--faces", "ideal-layer measures one frame from faces in line; not with --frames " +
                                                  std::to_string(frames));
    m.dims = {mesh, mesh, mesh};
    if (frameIndex < 0) frameIndex = frames - 1;  // this process renders the last frame of its sequence
    if (asBaseline || asFrame) frames = 1;        // the baseline is of the last frame's view; a frame is one frame
    if (asBaseline || asComparison || asFrame) {  // a reference run of another: no outputs (the caller reads its report)
        traceSpecs_.clear();
        traceWindow_.clear();
        vcd.clear();
        map.clear();
        image.clear();
        baseline = false;
        quiet = true;
        verbose = 0;  // (the parent says what it does)
    }
    if (asBaseline) {  // one node with the global costs: no per-node or per-link settings
        meshDims = "1x1x1";
        nodeCostSpecs_.clear();
        linkSpecs_.clear();
        m.nodeSpeed.clear();
        m.balance.policy = "none";  // one node has no boundary to slide
    }
    // (asComparison: the same machine and frame; the caller sets --balance.)
    // The reference runs' other policy has no faces to share.
    if ((asBaseline || asComparison) && m.balance.policy != "slide" && m.balance.policy != "resplit")
        m.balance.idealLayerFaces = false;
    if (!meshDims.empty()) {
        int x, y, z;
        char a = 0, b = 0;
        std::istringstream in(meshDims);
        if (!(in >> x >> a >> y >> b >> z) || a != 'x' || b != 'x' || !in.eof() || x < 1 || y < 1 || z < 1 || x > 16 ||
            y > 16 || z > 16)
            throw CLI::ValidationError("--mesh-dims", "expected XxYxZ with each in 1..16, got '" + meshDims + "'");
        m.dims = {x, y, z};
    }
    for (const std::string& s : nodeCostSpecs_) {
        const size_t colon = s.find(':'), eq = s.find('=');
        if (colon == std::string::npos || eq == std::string::npos || eq < colon)
            throw CLI::ValidationError("--node-cost", "expected x,y,z:NAME=TIME, got '" + s + "'");
        const Cell c = parseCell("--node-cost", s.substr(0, colon));
        auto it = m.nodeCosts.find(c);
        Costs& k = it == m.nodeCosts.end() ? (m.nodeCosts[c] = m.costs) : it->second;
        Picos* f = costField(k, s.substr(colon + 1, eq - colon - 1));
        if (!f) throw CLI::ValidationError("--node-cost", "unknown cost name in '" + s + "'");
        *f = timeOf("--node-cost", s.substr(eq + 1));
    }
    for (const std::string& s : linkSpecs_) {
        const size_t colon = s.find(':');
        if (colon == std::string::npos) throw CLI::ValidationError("--link-set", "expected x,y,z,DIR:settings, got '" + s + "'");
        const std::string where = s.substr(0, colon);
        const size_t lastComma = where.find_last_of(',');
        if (lastComma == std::string::npos) throw CLI::ValidationError("--link-set", "expected x,y,z,DIR, got '" + where + "'");
        const Cell c = parseCell("--link-set", where.substr(0, lastComma));
        const std::string dirText = where.substr(lastComma + 1);
        int dir = -1;
        for (int d = 0; d < kDirs; ++d)
            if (dirText == dirName(d)) dir = d;
        if (dir < 0) throw CLI::ValidationError("--link-set", "direction must be one of +x -x +y -y +z -z, got '" + dirText + "'");
        LinkParams p = m.link;
        std::istringstream items(s.substr(colon + 1));
        std::string item;
        while (std::getline(items, item, ',')) {
            const size_t eq = item.find('=');
            const std::string key = item.substr(0, eq), val = eq == std::string::npos ? "" : item.substr(eq + 1);
            if (key == "latency") p.latency = timeOf("--link-set", val);
            else if (key == "bandwidth") p.bandwidth = rateOf("--link-set", val);
            else if (key == "depth") {
                std::istringstream in(val);
                if (!(in >> p.depth) || !in.eof() || p.depth < 1) throw CLI::ValidationError("--link-set", "depth must be a positive integer, got '" + val + "'");
            } else if (key == "control_depth") {
                std::istringstream in(val);
                if (!(in >> p.controlDepth) || !in.eof() || p.controlDepth < 0)
                    throw CLI::ValidationError("--link-set", "control_depth must be a non-negative integer, got '" + val + "'");
            } else if (key == "out_depth") {
                std::istringstream in(val);
                if (!(in >> p.outDepth) || !in.eof() || p.outDepth < 0)
                    throw CLI::ValidationError("--link-set", "out_depth must be a non-negative integer, got '" + val + "'");
            } else throw CLI::ValidationError("--link-set", "unknown setting '" + key + "' (latency, bandwidth, depth, control_depth, out_depth)");
        }
        m.linkOverride[{c, dir}] = p;
    }
    for (const std::string& s : traceSpecs_) m.traceNodes.push_back(parseCell("--trace-nodes", s));
    for (const std::string& s : traceLinkSpecs_) {  // x,y,z[,DIR|fb]
        const size_t commas = size_t(std::count(s.begin(), s.end(), ','));
        if (commas == 2) {
            m.traceLinks.push_back({parseCell("--trace-links", s), -1});
            continue;
        }
        const size_t last = s.find_last_of(',');
        const std::string dirText = s.substr(last + 1);
        int dir = dirText == "fb" ? kDirs : -1;
        for (int d = 0; d < kDirs; ++d)
            if (dirText == dirName(d)) dir = d;
        if (commas != 3 || dir < 0)
            throw CLI::ValidationError("--trace-links", "expected x,y,z or x,y,z,DIR with DIR one of +x -x +y -y +z -z fb, got '" + s + "'");
        m.traceLinks.push_back({parseCell("--trace-links", s.substr(0, last)), dir});
    }
    if (!traceWindow_.empty()) {
        const size_t comma = traceWindow_.find(',');
        if (comma == std::string::npos) throw CLI::ValidationError("--trace-window", "expected FROM,TO, got '" + traceWindow_ + "'");
        m.traceFrom = timeOf("--trace-window", traceWindow_.substr(0, comma));
        m.traceTo = timeOf("--trace-window", traceWindow_.substr(comma + 1));
    }
    m.vcdPath = vcd;
    // After every link and balancing setting: each process's lookahead
    // depends on its links and on the smallest message they carry.
    m.lookaheadQuantum = quantum_ == "lookahead";
    if (m.lookaheadQuantum) {
        m.quantum = m.lookahead();
    } else {
        const auto q = parseTime(quantum_);
        if (!q) throw CLI::ValidationError("--quantum", "expected 'lookahead' or a non-negative time with a unit (ps ns us ms s), got '" + quantum_ + "'");
        m.quantum = *q;
    }
    m.balance.axis = scene.axis == "x" ? 0 : scene.axis == "y" ? 1 : 2;  // one progress axis for scene and balancing
    try {
        m.validate();
    } catch (const std::invalid_argument& e) {
        const std::string msg = e.what();
        const size_t colon = msg.find(':');
        throw CLI::ValidationError(msg.substr(0, colon), msg.substr(colon + 2));
    }
}

}  // namespace rt
