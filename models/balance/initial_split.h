// Where a frame starts (doc/machine.md, "A node"; doc/balancing.md): each
// column's boundaries along the progress axis, each node's box, which node
// generates each primary ray, and how the host's credit is shared out for
// the end-of-frame protocol (credit.h). Plain functions of the
// configuration and the scene, run before the simulation.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "camera.h"
#include "channel/credit.h"
#include "lattice.h"
#include "config/machine_config.h"
#include "ray_job.h"
#include "region.h"

namespace rt {

// Per column (ColumnGeometry order): its N + 1 planes along the axis, the
// world's ends included.
using ColumnPlanes = std::vector<std::vector<double>>;

// The thinnest a node's box may become along the axis: --min-thickness of
// a uniform slice of the world.
double minThicknessOf(const MachineConfig& cfg, const Box& world);

// A split given from outside that does not fit this mesh (a report's, by
// --boundaries-from): bad input, not a failed run.
struct SplitError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// `planes` with each column's inner planes replaced by `inner`'s, for
// `what` ("start boundaries", "target boundaries"). Throws SplitError,
// naming `what`, if `inner` has another number of
// columns or of planes in one, or a box thinner than minThickness (less
// `slack` of it).
ColumnPlanes withInnerPlanes(const char* what, ColumnPlanes planes, const std::vector<std::vector<double>>& inner,
                             double minThickness, double slack);

// --start-mix auto: the mix `median` and `sample` start at, and why (for
// the report). `median` is the object median (1). `sample` spends its
// sample at the start's pace, so the start should follow the work: where
// one of the scene's intersection tests (their mean) costs at least a third
// of what a ray's hop keeps a processor or a link busy (its share of a ray
// message's --cost-send, --cost-recv and wire), the objects are the work: 1;
// else the hops are, and half by the length keeps the boxes the rays cross
// short: 0.5. Where a test costs less than a tenth of a hop, the rays
// passed on between columns whose faces differ cost more than fitting each
// column's objects gains: every column starts at the same planes, the
// quantiles of all the objects (doc/balancing.md, "Where sample starts").
// On columns of more than 8 boxes, whatever the costs, the uniform split
// (0): a ray's hops grow with the boxes it crosses; a box the half start
// made long carries the rays across its sides, and each box the object
// median made thin costs a ray a hop. For the same
// reason a column whose heaviest box (by object centres) the half start
// leaves as heavy as the uniform split's keeps the uniform split
// (StartMix::lighterOnly): tetra-3's triangles fill every slab alike.
// A scene's intersection test (the mean over its objects, at the nodes'
// speed) against what a ray's hop keeps a processor or a link busy (its
// share of a ray message: --cost-send and --cost-recv, or the sender's alone
// on the link's engine with --hop-handling link, and the message's bytes on
// the wire), in ps; whether the tests are the work (a test costs at least a
// third of a hop), or cheap (less than a tenth); said in words.
struct TestAgainstHop {
    double test, hop;
    bool testsAreTheWork, cheap;
    std::string costs;  // "a test (10 ns) costs less than a third of a ray's hop (212 ns)"
    double wire = 0, handling = 0;  // ps a ray: on the link (its engine included), on the processors at both ends
    // A hop's time on the wire against its handling on the processors:
    // where the wire is at least kWirePerHandling handlings, the links set
    // the frame. 0 where the links' engines handle the hop (no machine of
    // that kind was measured for it).
    double wirePerHandling() const { return handling > 0 ? wire / handling : 0.0; }
};
TestAgainstHop testAgainstHop(const MachineConfig& cfg, const std::vector<Shape>& objects);

struct StartMix {
    double mix;
    bool aligned;     // one set of planes for every column, from all the objects
    std::string why;  // "auto: a test (10 ns) costs less than a third of a ray's hop (212 ns): ..."
    // A column whose heaviest box (by object centres) the start leaves as
    // heavy as the uniform split's starts uniform instead (auto's half start).
    bool lighterOnly = false;
    // The weight of where the column's primary rays enter the world in its
    // quantiles (the rest: `mix` as above): the node whose box a primary
    // ray enters generates it, however thin the box. Where the objects are
    // the work (the object median) generating a ray can still cost as much
    // as a few tests (generationWeight); elsewhere 0.
    double generation = 0;
};
// A primary ray's generation against itself and kTestsPerGeneration of the
// scene's intersection tests (at the nodes' speed; the constant is in
// config/start_constants.h, which the help text states it from): 0.21
// on the paper's machine, 0.0025 with the modern machine's sphere tests
// x100. Measured on
// Fig. 4's scene on the paper's machine at f = 1/N, N = 4 to 8, both views
// (doc/balancing.md, "Where sample starts"): at 0.2 every first frame was
// within 1.2 times max(1/N, the best static split); at 0.1, 0.15 and 0.32
// one was not.
double generationWeight(const MachineConfig& cfg, double test);
StartMix startMixFor(const MachineConfig& cfg, const std::vector<Shape>& objects);
// cfg.balance.startMix, startAligned and startMixWhy set from startMixFor, if auto and
// the policy starts at the objects, not where a frame before left them (so
// the report echoes the mix used, and only if it is used).
void chooseStartMix(MachineConfig& cfg, const std::vector<Shape>& objects);
// --sample-end auto: balance/sample_end.h.

// The planes each column starts with: where a frame before left them
// (cfg.startBoundaries, each box at least `minThickness`), or the policy's
// own start: uniform (`cuts`, the paper), or for `median` and `sample` at
// the quantiles of the object centres in the column, or in the world where
// the start is aligned (mixed with its length: cfg.balance.startMix, or
// startMixFor's if auto). Throws std::invalid_argument for
// start boundaries that do not fit the mesh.
// With `camera`, where its primary rays enter the world counts for
// StartMix::generation (else not).
ColumnPlanes initialPlanes(const MachineConfig& cfg, const Lattice& cuts, const Box& world, const ObjectBins& bins,
                           double minThickness, const Camera* camera = nullptr);

// Node c's box: its cell of the uniform split, with the column's planes along the axis.
Box nodeBox(const Cell& c, const Lattice& cuts, const ColumnGeometry& g, const ColumnPlanes& planes);

// The host's job description: each primary ray goes to the node that owns
// the point where it starts inside the world box (by `planes` along the
// axis); rays that miss the world are the background, which the host fills
// in itself. `stride` > 1: only the pixels (stride/2 + i stride, stride/2 +
// j stride), a calibration frame's (MachineConfig::pixelStride).
struct PrimaryRays {
    std::vector<std::vector<uint32_t>> perNode;  // pixels, by node index
    std::vector<RayJob> misses;                  // primary rays that miss the world box
};
PrimaryRays assignPrimaryRays(const Camera& camera, const Box& world, const Lattice& cuts, const ColumnGeometry& g,
                              const ColumnPlanes& planes, int stride = 1);
// The same primary rays' entry points into the world along the axis, by
// column (column index), sorted (StartMix::generation).
std::vector<std::vector<double>> primaryEntries(const Camera& camera, const Box& world, const Lattice& cuts,
                                                const ColumnGeometry& g, int stride = 1);
// How many of a row's (or a column's) n pixels that stride traces.
inline int stridedCount(int n, int stride) { return (n - stride / 2 + stride - 1) / stride; }

// Credit (weight throwing): the host keeps what it does not hand out; each
// node with P > 0 primary rays gets 2^-hostExp (hostExp = ceil(log2 of the
// nodes with any)) and gives each of them 2^-exp, exp = hostExp +
// ceil(log2 P), keeping the rest. The parts sum to exactly 1.
struct CreditShares {
    std::vector<int> exp;            // per node: its primary rays' exponent (0: none)
    std::vector<Credit> remainder;   // per node: what it keeps of its share
    Credit host;                     // what the host keeps
};
CreditShares shareCredit(const std::vector<std::vector<uint32_t>>& perNode, int maxExp);

}  // namespace rt
