// Everything that configures the machine: mesh shape, per-operation costs,
// node speeds, link and frame-buffer port settings, with per-node and
// per-link overrides. Plain data with named fields (no globals); rtsim fills
// it from its command line or config file. Defaults and where their values
// come from: doc/machine.md, "Costs".
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "lattice.h"
#include "channel/link_params.h"
#include "base/mesh_geometry.h"
#include "base/param.h"
#include "base/units.h"
#include "config/start_constants.h"

namespace rt {

// Processing cost of each operation, before the node's speed factor.
struct Costs {
    std::array<Picos, 3> test{10000, 20000, 20000};  // intersection test: sphere, polygon, cone
    Picos voxelStep = 4000;
    Picos rayGen = 20000;   // generating one primary ray
    Picos shade = 50000;    // shading one hit (spawning its rays and contributions)
    Picos send = 40000;     // handling one outgoing message (link or frame-buffer port)
    Picos recv = 40000;     // handling one incoming message
};

// The costs a flag sets (base/param.h): --cost-NAME, --node-cost's NAMEs, the report's config.costs and node_costs.
inline const std::vector<Param<Costs>>& costParams() {
    static const std::vector<Param<Costs>> rows = {
        timeParamAt<Costs>("sphere", [](Costs& c) -> Picos& { return c.test[0]; }, "/test_sphere_ns", "intersection test, sphere"),
        timeParamAt<Costs>("polygon", [](Costs& c) -> Picos& { return c.test[1]; }, "/test_polygon_ns", "intersection test, polygon"),
        timeParamAt<Costs>("cone", [](Costs& c) -> Picos& { return c.test[2]; }, "/test_cone_ns", "intersection test, cone/cylinder"),
        timeParam("voxel", &Costs::voxelStep, "/voxel_step_ns", "one voxel step of the 3D-DDA"),
        timeParam("raygen", &Costs::rayGen, "/ray_generation_ns", "generating one primary ray"),
        timeParam("shade", &Costs::shade, "/shading_ns", "shading one hit"),
        timeParam("send", &Costs::send, "/send_ns", "handling one outgoing message"),
        timeParam("recv", &Costs::recv, "/receive_ns", "handling one incoming message"),
    };
    return rows;
}

// Sliding boundaries (doc/balancing.md). Every column of nodes along the
// progress axis owns its own boundaries between them. Policies are named
// (models/config/policy_table.cpp): none, slide, work, quantile, resplit, measured, median.
// The recommended policy (doc/balancing.md, "The recommended policy";
// `--balance recommended`; the default of --balance is none, no
// balancing): `sample`, which balances the first frame, on columns of 2 to
// kLongestColumnSampled boxes (none on columns of one); `measured` on longer ones, which keeps
// the starting split for the first frame, measuring where the work is, and
// from the second frame on re-splits each column between frames as
// `resplit` (and sample's later frames) do. On columns of 16 to 64 boxes
// sample's first frame lost at 3 of 62 SPD points (by its move, or by its
// sample's pixels going first), measured's at none: the sample's sum climbs
// such a column for most of the frame, and the hops its planes add are not
// in it.
constexpr int kLongestColumnSampled = 8;
struct PolicyChoice {
    const char* policy;
    std::string why;  // "sample: columns of 4 boxes (at most 8)"
};
PolicyChoice recommendedPolicy(const std::array<int, 3>& dims, int axis);

// --start-mix auto, the default: a value outside the mixes' range [0, 1].
constexpr double kStartMixAuto = -1;

// --polish-tries auto: kSamplePolishTries under sample (the recommended
// policy on columns of at most 8 boxes), else 0 (resplit and measured,
// where it was not measured), the default: balancing.md, "Polish".
constexpr int kPolishTriesAuto = -1;
constexpr int kSamplePolishTries = 8;
constexpr const char* kPolishTriesHelp =
    "resplit, measured, sample: once the sequence would hold, this many frames each try a small move of the planes "
    "held (the busiest node's box shrunk, or every plane shifted along the axis), keeping the faster; then the "
    "fastest planes are held (0: off; auto: 8 under sample, else 0)";

struct BalanceConfig {
    std::string policy = "none";
    int axis = 0;                 // progress axis: 0 x, 1 y, 2 z
    Picos interval = 20000000;    // 20 us between load reports
    double gain = 0;              // how far a decision moves (the policy's; 0: its default, gainOf())
    double deadband = 0.05;       // no slide while the difference is at most this (the policy's measure)
    double minThickness = 0.05;   // a box never gets thinner than this fraction of its initial thickness
    // Where median and sample start: each column's boundaries at the
    // quantiles of startMix x the objects' centres + (1 - startMix) x the
    // column's length (1: the object median; doc/balancing.md, "Where sample
    // starts"). kStartMixAuto: chosen from the machine's costs and the view
    // (startMixFor, weighStartLinks), startMixWhy says how.
    double startMix = kStartMixAuto;
    bool startAligned = false;  // (set with startMix by auto: every column at the world's quantiles)
    bool startLighterOnly = false;  // (set with startMix by auto: a column whose heaviest box the start does not lighten starts uniform)
    double startGeneration = 0;  // (set with startMix by auto: the primary rays' entry points' weight in the start's quantiles)
    std::string startMixWhy;
    // When `sample`'s gather starts up a column (doc/balancing.md, "When the
    // sample is done"): false (generated), once its lowest node has generated
    // its sample's primary rays; true (credit), once the frame buffer has
    // every sample ray's credit back and tells the column's lowest node, the
    // sample's rays going ahead of the rest on the control lane. With
    // sampleEndAuto (--sample-end auto, the default) chosen from the
    // machine's costs as the start mix is, and the view (chooseSampleEnd,
    // balance/sample_end.h), sampleEndWhy says how.
    bool sampleCredit = false;
    bool sampleEndAuto = true;
    std::string sampleEndWhy;
    // `sample`'s sum counts its rays across the planes; a part is at least its link up (ColumnSample::cross).
    // It acts only where sample gathers a sample, on columns of at most kLongestColumnSampled
    // boxes (elsewhere the command line refuses it given on). Off by default: on, Fig. 4's first
    // frames on the 1987 machine along the axis at N = 7 and 8 lose (doc/balancing.md, "The recommended policy").
    bool sampleLinks = false;
    // Set where --balance recommended chose the policy (recommendedPolicy): which, and why.
    std::string recommendedWhy;
    // --balance as given, for a message: "recommended (sample here)" where
    // the recommended policy was chosen, else the policy's name.
    std::string asGiven() const { return recommendedWhy.empty() ? policy : "recommended (" + policy + " here)"; }
    int bins = 16;                // work profile: bins per initial box thickness along the axis
    // Between frames, once the sequence would hold: frames that try small
    // moves of the planes held, keeping the faster (between_frames.h, "Polish").
    int polishTries = kPolishTriesAuto;  // (auto: RtsimOptions::finish() makes it 8 under sample, else 0)
    Picos rebuildCost = 20000;    // updating a node's grid: per object moved in or out
    // The guard (every policy; balance_agent.h): no slide on loads older than
    // maxAge intervals, or whose cost exceeds the work it moves over the
    // next `horizon` intervals.
    bool guard = true;
    double maxAge = 4;
    double horizon = 10;
    double hopRatio = 4;          // no slide while a ray's hop takes longer than this many mean steps
    // No slide across a link that would be busy more than this share of an
    // interval after it (its last interval's share plus the rays the slab's
    // work sends across, by the link's narrower limit: its wire, or its
    // slots' round trips; 1: a full link, the default; 0: off;
    // doc/balancing.md, "A busy-link guard").
    double wireShare = 1;
    // Load reports on a control lane take at most this share of the link's
    // time: a node reports to a neighbour again only once reportTime /
    // reportShare has passed since its last report there (balance_agent.h,
    // "Pacing"; on the rays' FIFO reports wait their turn and are not paced).
    double reportShare = 0.02;
    // Faces shared by a layer and agreed at no cost (ideal_layer_faces.h): a
    // measuring device for `slide`, off on a real machine.
    bool idealLayerFaces = false;

    bool dynamic() const;         // a policy that moves boundaries during the frame
    // A policy that re-splits from the frame before's work (resplit, measured).
    bool betweenFrames() const { return policy == "resplit" || policy == "measured" || policy == "sample"; }
    // One that starts at a split of its own, from the objects (startMix).
    bool startsAtObjects() const { return policy == "median" || policy == "sample"; }
    bool firstFrameHolds() const { return policy == "measured"; }  // its first frame keeps its split, measures
    std::string named() const;  // 'policy', or with --balance recommended's choice and why (for errors)
    // One whose later frames try once a re-split forecast to gain less than
    // the margin a move needs (sample: between_frames.h, "One try").
    bool triesWithinTheMargin() const { return policy == "sample"; }
    // One whose boxes never move, within a frame or between frames (none, median): --fidelity express's.
    bool boxesStayPut() const { return policy == "none" || policy == "median"; }
    double gainOf() const;        // gain, or the policy's default
    // Throws std::invalid_argument("--flag: what") for the first bad value.
    // `reportFloor`: the shortest interval a node can report in;
    // `carriedBoundaries`: the frame starts where another left its faces.
    void validate(Picos reportFloor, bool carriedBoundaries) const;
};

// --start-mix's help: how auto chooses, with the constants it uses; --sample-links's, where it acts.
const std::string& startMixHelp();
const std::string& sampleLinksHelp();
// The refusal of a sample's flag under another policy: "only sample gathers a sample, not 'measured'".
std::string onlySampleGathers(const std::string& named);
// The balancing settings a flag sets (base/param.h), echoed in the report's
// config.balance; --balance (the policy) and --no-guard are read by the
// command line itself, and the echo's gain is gainOf().
inline const std::vector<Param<BalanceConfig>>& balanceParams() {
    using B = BalanceConfig;
    static const std::vector<Param<B>> rows = {
        specialParam<B>("balance", nullptr),
        timeParam("balance-interval", &B::interval, "/interval_ns", "time between load reports"),
        shownAs(numberParam("gain", &B::gain, 0, std::numeric_limits<double>::infinity(), nullptr,
                            "slide: step = gain x load difference x thickness; work: share of the busy-time gap moved; "
                            "quantile: share of the way to the target"),
                "0: the policy's, slide and work 0.25, quantile 0.5"),
        numberParam("deadband", &B::deadband, 0.0, 0.999, "/deadband", "no slide while the load difference is at most this"),
        numberParam("min-thickness", &B::minThickness, 1e-6, 1.0, "/min_thickness",
                    "guard: a box keeps at least this fraction of its initial thickness"),
        orWord(numberParam("start-mix", &B::startMix, 0.0, 1.0, "/start_mix", startMixHelp().c_str()),
               "auto", kStartMixAuto),
        orWord(choiceParam("sample-end", &B::sampleCredit, "credit", "generated", "/sample_end",
                           "sample: when a column's gather starts: generated, once its lowest node has generated its "
                           "sample's primary rays; credit, once the frame buffer has every sample ray's credit back and "
                           "says so (the sample's rays go first, on the links' control lane: a mesh link without one gets "
                           "one as deep as the link); auto: credit where an intersection test costs at least a third of a "
                           "ray's hop (as --start-mix auto's object median), or where only the columns' top nodes generate "
                           "the sample's primary rays (a view from beyond the axis's far end), else generated"),
               "auto", &B::sampleEndAuto),
        choiceParam("sample-links", &B::sampleLinks, "on", "off", "/sample_links", sampleLinksHelp().c_str()),
        specialParam<B>("no-guard", "no guard: slide on loads however old, and whatever the slide costs against the work it moves"),
        numberParam("max-age", &B::maxAge, 0.0, 1e9, "/max_age_intervals", "guard: no slide on loads older than this many intervals"),
        numberParam("guard-hop", &B::hopRatio, 0.0, 1e9, "/guard_hop_steps",
                    "guard: no slide while a ray's hop to the neighbour (latency + wire) takes longer than this many of "
                    "the giver's mean ray steps"),
        numberParam("guard-wire", &B::wireShare, 0.0, 1e9, "/guard_wire_share",
                    "guard: no slide across a link that would be busy more than this share of an interval after it: the "
                    "last interval's share plus a ray message per ray step the slab's work took, each by the link's "
                    "narrower limit, its wire or its slots (1: a full link; 0: off)"),
        numberParam("guard-horizon", &B::horizon, 0.0, 1e9, "/guard_horizon_intervals",
                    "guard: no slide that costs more than the work it moves over this many intervals"),
        numberParam("report-share", &B::reportShare, 1e-6, 1.0, "/report_share",
                    "load reports on a control lane take at most this share of the link's time: a node reports to a "
                    "neighbour again only once a report's time on the wire divided by this has passed"),
        choiceParam("faces", &B::idealLayerFaces, "ideal-layer", "column", "/faces",
                    "column: each column moves its own faces (the machine); ideal-layer: a measuring device, faces shared "
                    "by a layer and moved by slide's rule on the layer's summed loads, read without messages "
                    "(doc/balancing.md)"),
        numberParam("bins", &B::bins, 1, 4096, "/bins", "work profile: bins per box thickness along the axis"),
        orWord(numberParam("polish-tries", &B::polishTries, 0, 1000, "/polish_tries", kPolishTriesHelp), "auto",
               kPolishTriesAuto),
        timeParam("cost-rebuild", &B::rebuildCost, "/rebuild_cost_ns", "updating a node's grid, per object moved in or out"),
    };
    return rows;
}

// The mesh's limits: nodes per axis, and nodes in all (32 x 32 x 32, or a
// flatter shape such as 64 x 64 x 8); a run that would not fit the
// machine's memory is refused before it starts with its estimate
// (binning_memory.h).
constexpr int kMaxNodesPerAxis = 64;
constexpr long kMaxNodes = 32768;

struct MachineConfig {
    std::array<int, 3> dims{4, 4, 4};  // nodes along x, y, z
    int width = 0, height = 0;         // image size (0: the scene's)
    int maxDepth = 5;

    Costs costs;
    double speed = 1.0;                // node speed factor: time = cost / speed
    std::map<Cell, double> nodeSpeed;  // per-node speed overrides
    std::map<Cell, Costs> nodeCosts;   // per-node cost overrides (whole sets)

    LinkParams link;
    std::map<std::pair<Cell, int>, LinkParams> linkOverride;  // (source node, direction)

    // Who pays for a hop (doc/machine.md, "Who pays for a hop"): the node's
    // processor handles each message it sends and receives (--cost-send,
    // --cost-recv charged to its busy time, as a node whose routing runs in
    // software), or the links' own engines do (DMA, as the paper's simulator
    // assumes): then the sender's --cost-send holds the wire before each
    // message (LinkParams::engine) and the receiver's --cost-recv adds to the
    // link's latency, and the processors pay nothing for a hop.
    bool hopsByLinks = false;  // --hop-handling link

    // The fidelity rung (doc/fidelity.md): false, the exact model; true,
    // express: rays cross the boxes whose nodes have no work of their own
    // through one relay process, not the nodes' (channel/express.h).
    bool express = false;  // --fidelity express
    // through: express, and also past boxes with objects that a ray crosses
    // without a hit (channel/express.h): their nodes' processors take the
    // relay's passes among their own steps in the order booked.
    bool through = false;  // --fidelity through
    // Either rung: rays go through the express relay.
    bool usesRelay() const { return express || through; }
    const char* relayRung() const { return through ? "through" : "express"; }  // (its name, where usesRelay)
    // A session whose later frames may turn express on (--max-error's
    // calibration frames, tb/fidelity_choice.h) builds the express routes
    // and relay even where express is off: a frame without express then
    // runs as the exact model, its relay idle.
    bool expressRoutes = false;
    // A calibration frame's (tb/fidelity_choice.h): only the pixels
    // (stride/2 + i stride, stride/2 + j stride) get primary rays, the
    // others stay black; 1: every pixel.
    int pixelStride = 1;

    // The frame buffer (doc/machine.md, "The frame buffer"): fbUnits units,
    // pixel-interleaved (pixel p in unit p mod fbUnits); 1 is a single host.
    // Each node has a port to each unit (and each unit but 0 one to unit 0).
    int fbUnits = 16;
    LinkParams fbPort{200000, 1e9, 16};
    Picos hostCost = 5000;             // per contribution accumulated, in its unit
    int fbBatch = 32;                  // contributions per frame-buffer message
    int rayBatch = 1;                  // rays per link message (sent when full or before the node waits)
    // The order in which a node generates its primary rays: false, the
    // host's (row by row); true, spread through its pixels
    // (node/primary_queue.h, spreadOrder).
    bool spreadPrimaries = false;  // --primary-order spread

    BalanceConfig balance;
    // Where each column's boundaries along the progress axis start: per
    // column (in Machine::columnOf order), its N - 1 inner planes, each box
    // at least the minimum thickness; empty: the policy's own start (uniform,
    // or the object medians for `median`). A frame of --frames starts where
    // the one before ended (--boundaries-from).
    std::vector<std::vector<double>> startBoundaries;
    // `resplit`: where each column's inner planes go at the start of the
    // frame (the quantiles of the frame before's busy time; same layout as
    // startBoundaries). The nodes move there with slides at time 0 and keep
    // their boxes for the frame; empty: no frame before (within-frame slides).
    std::vector<std::vector<double>> targetBoundaries;

    // What the links keep of each message beyond counts and times: their
    // latency distributions (p50, p95, max) and their backlog and buffer
    // high-water marks. Keeping them costs wall time (each touches a link's
    // figures once per message, long after the link was last used; how much:
    // doc/exploration.md, "Fidelity knobs"); without them (--link-stats
    // counts) the report leaves those fields out and everything else,
    // timing included, is the same to the bit (doc/machine.md, the report).
    bool linkDistributions = true;

    // Tracing (VCD); empty path: none. The VCD is streamed into vcdPath;
    // its .gtkw (MachineResult::gtkw) opens it by vcdName's file name (rtsim:
    // streams into a temporary file, renamed to --vcd at the end; empty
    // vcdName: vcdPath's).
    std::string vcdPath, vcdName;
    std::vector<Cell> traceNodes;      // empty: every node
    // Links traced besides the traced nodes' own: (node, direction), the
    // direction kDirs for its frame-buffer port, -1 for all of them.
    std::vector<std::pair<Cell, int>> traceLinks;
    Picos traceFrom = 0, traceTo = ~Picos(0);

    // Temporal decoupling (TLM-2.0 style): a process may run this far ahead of
    // the kernel's time before it synchronises. 0: synchronise after every
    // step (exact). No larger than the lookahead: still exact, because no
    // message can arrive sooner than one latency and its own time on the
    // wire after the kernel's time (doc/time.md, "Local time").
    Picos quantum = 0;
    // --quantum lookahead (the default): each process runs ahead by its own
    // lookahead instead, the largest quantum that is still exact for it: the
    // soonest a message not yet sent can arrive at it, the smallest over its
    // input links of their latency plus the smallest message's time on
    // their wire (Machine; doc/time.md, "Local time"). `quantum` then
    // holds the smallest of them (lookahead()), for the report.
    bool lookaheadQuantum = false;
    // With lookaheadQuantum: how late the frame-buffer units other than 0
    // may take the nodes' contributions (FrameBufferUnit::setLate), so that
    // one activation takes many; the simulated times are the same (0: as
    // they arrive). Not with waveforms or --fb-out-depth.
    Picos fbLate = 10000000;  // 10 us

    bool showProgress = false;

    // The watchdog (machine.h): a run in which no ray, contribution or
    // credit moves for watchdogSpan of simulated time (0: the larger of
    // 100 us and 1,000 times the largest cost, latency or ray message's wire
    // time: nothing in a running frame waits that long),
    // or that runs longer than watchdogWall seconds of wall-clock time (0:
    // no limit), stops as incomplete.
    Picos watchdogSpan = 0;
    double watchdogWall = 0;
    // Test only: unit 0 drops the first credit message it takes, so the
    // frame never completes (the watchdog's planted bug).
    bool faultDropFirstCredit = false;

    int nodeCount() const { return dims[0] * dims[1] * dims[2]; }
    double speedOf(const Cell& c) const;
    const Costs& costsOf(const Cell& c) const;
    const LinkParams& linkOf(const Cell& from, int dir) const;
    // As the machine builds them, with the hop handling applied: the mesh
    // link from `from` towards `dir`, the node's frame-buffer port, the
    // costs its processor pays.
    LinkParams meshLinkOf(const Cell& from, int dir) const;
    LinkParams fbPortOf(const Cell& from) const;
    Costs processorCostsOf(const Cell& c) const;
    // The machine's lookahead: the smallest of its processes' (see
    // lookaheadQuantum): over every mesh link and frame-buffer port, its
    // latency plus the smallest message it carries on its wire (a link with
    // a control lane: its latency alone, for its sender). A quantum up to
    // this is still exact for every process.
    Picos lookahead() const;
    // The watchdog's span: watchdogSpan, or its default for a scene of
    // `objects` objects.
    Picos watchdogSpanOrDefault(size_t objects) const;
    // Throws std::invalid_argument("--flag: what") for the first bad value.
    void validate() const;
    // The times the model derives from the flags for one event, each at
    // most kMaxTimeValue (1,000 s) like any time given: a full message's
    // time on each link's wire, a full frame-buffer message's handling,
    // each cost at the slowest node's speed, a slide's grid update for all
    // `objects`, a load report's pacing gap. Throws std::invalid_argument
    // ("--flag: what") naming the flags (derived_times.cpp). Sums of them
    // are checked in the run as they are made (units.h).
    // `sumBytes`: the largest balancing message the policy sends up a column
    // (a sample's sum; 0: none), on every link's wire too.
    void checkDerivedTimes(size_t objects, uint32_t sumBytes = 0) const;
};

// The machine's parameters in the order rtsim's --help lists them (and a
// report's rerun.flags records them), with the other tables' rows in their
// places (base/param.h). A field without a row here (the image size, the
// trace's settings, the boundaries) is set by rtsim's other flags.
inline const std::vector<Param<MachineConfig>>& machineParams() {
    using M = MachineConfig;
    static const char *gm = "Machine", *gc = "Costs", *gl = "Links", *go = "Outputs";
    static const std::vector<Param<M>> rows = {
        specialParam<M>("mesh", "nodes per axis: an N x N x N mesh (at most 32: 32,768 nodes)", gm),
        specialParam<M>("mesh-dims",
                        "mesh shape XxYxZ instead of --mesh: each 1..64, at most 32,768 nodes (such as 64x64x8); a mesh "
                        "whose grids would not fit in memory is refused with the estimate",
                        gm),
        numberParam("max-depth", &M::maxDepth, 0, 39, "/max_depth", "mirror/refraction levels below the primary ray", gm),
        choiceParam("primary-order", &M::spreadPrimaries, "spread", "scan", "/primary_order", "each node's primary rays: scan "
                    "(row by row) or spread (a stride through its pixels: work reaches every box evenly; same image; doc/machine.md)", gm),
        partParam<M>("costs", gc),
        choiceParam("hop-handling", &M::hopsByLinks, "link", "processor", "/hop_handling",
                    "who pays for a hop: processor (each node's busy time pays --cost-send and --cost-recv per message) "
                    "or link (the links' engines do: --cost-send holds the wire before each message, --cost-recv adds to "
                    "the latency; the processors pay nothing for a hop)",
                    gc),
        timeParam("cost-host", &M::hostCost, "/host_cost_ns", "frame buffer: accumulating one contribution", gc),
        above(numberParam("speed", &M::speed, 0.0, std::numeric_limits<double>::infinity(), "/speed",
                          "node speed factor (time = cost / speed)", gc)),
        specialParam<M>("node-speed", "speed factor of one node: x,y,z=SPEED (repeatable)", gc),
        specialParam<M>("node-cost", nullptr, gc),
        specialParam<M>("quantum", "temporal decoupling: how far a process may run ahead of the kernel. 'lookahead': "
                        "each process's own, the largest that is still exact (its input links' latency plus the smallest "
                        "message's time on their wire); 0: synchronise after every step (also exact, slower); a time: every "
                        "process by that much, exact up to the smallest lookahead, beyond it faster and timing approximate", gm),
        orWord(choiceParam("fidelity", &M::express, "express", "exact", "/fidelity/rung", "exact (every hop an event); "
                           "express (rays cross boxes with no objects in one relay, timed as the exact model but for the "
                           "order of those nodes' own work against the rays); or through (express, and past boxes with "
                           "objects a ray crosses without a hit where their nodes are free); --balance none or median; "
                           "doc/fidelity.md", gm), "through", &M::through),
        specialParam<M>("max-error", "the render-time error you accept (2% or 0.02): rtsim picks --fidelity, the fastest "
                                     "rung within it on a calibration frame, or exact where a calibration would not pay "
                                     "(doc/fidelity.md)", gm),
        partParam<M>("link", gl),
        choiceParam("link-stats", &M::linkDistributions, "full", "counts", "/link_stats",
                    "what the links keep beyond message counts, bytes, wire, wait and backlog times: full (also latency "
                    "percentiles, backlog and buffer high-water marks and the busiest window's utilisation) or counts "
                    "(not those: a 100 us run about 7 % faster; timing unchanged)", gl),
        specialParam<M>("link-set", nullptr, gl),
        numberParam("fb-units", &M::fbUnits, 1, 256, "/fb_units",
                    "frame-buffer units, pixel-interleaved (pixel p in unit p mod K), each with a port from every node; "
                    "1: a single host", gl),
        partParam<M>("fb-port", gl),
        numberParam("ray-batch", &M::rayBatch, 1, 65536, "/ray_batch", "rays per link message (sent when full or before a node waits)", gl),
        numberParam("fb-batch", &M::fbBatch, 1, 65536, "/fb_batch", "contributions per frame-buffer message", gl),
        partParam<M>("balance", "Balancing (sliding boundaries)"),
        timeParam("watchdog", &M::watchdogSpan, "/watchdog/span_ns",
                  "stop a run in which no ray, contribution or credit moves for this long in simulated time (exit 3, the "
                  "report and VCD so far marked incomplete); 0: the larger of 100 us and 1,000 times the largest cost, "
                  "latency or ray wire time",
                  go),
        numberParam("watchdog-wall", &M::watchdogWall, 0.0, 1e9, "/watchdog/wall_s",
                    "also stop it after this many seconds of wall-clock time (0: no limit)", go),
        specialParam<M>("fault-drop-credit", "test only: unit 0 loses the first credit it takes", ""),
    };
    return rows;
}

}  // namespace rt
