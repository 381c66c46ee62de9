// `sample` (doc/balancing.md, "One frame: sample, then split"): the first
// frame's primary rays that make up its sample, a column's sample as the
// gather carries it, and the planes it gives. Plain C++: the protocol that
// gathers the sample along the column and moves the planes is
// balance_sample.cpp.
//
// Why a sample: the paper's rule moves a boundary by the load difference of
// two neighbours, one slab at a time, so in one frame most planes of a
// column never move (doc/balancing.md, "One frame: sample, then split"). A
// sample of the frame's rays, spread evenly over the image and generated
// first, shows where the whole frame's work is early on; every plane of the
// column then moves once, to where that work splits evenly.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "balance/move_forecast.h"
#include "channel/message.h"

namespace rt {

// The sample: the pixels on every kSampleSide-th row and column, one in 16.
// A regular pattern, not a random one: a random sample of the same size
// put the planes worse, and smaller samples worse again (doc/balancing.md).
constexpr uint32_t kSampleSide = 4;
bool inSample(uint32_t pixel, uint32_t width);

// A node records its sample's work in this many equal bins over its box
// (which holds still while it samples): finer where the boxes are thin, as
// where the objects crowd.
constexpr int kSampleBins = 64;
// The gather's messages carry the column's sample in at most this many
// cells (8 bytes an edge and a mass each): past it, the cells are merged
// to equal shares of the work, so a message stays about 1 KB however long
// the column. The sum travels up behind the sample's rays, and every ray
// sent up after it waits behind it on each link: a sum slower a hop than
// a ray holds them all to its pace (doc/balancing.md, "Long columns"; the
// figures for 64: doc/history.md). Where the sum carries the sides' passes
// too (a column with columns beside it), the sides take their room from the
// cells, and so do the faces (which every sum carries, for the price of a
// move: sampleMovePs): the message stays at kSampleValues values, and one
// more a box (what passing its objects on costs).
constexpr int kSampleCells = 64;
constexpr int kSampleValues = 2 * kSampleCells + 5;
// The largest sum's message, the bytes it takes on a link's wire (checked
// before the run: MachineConfig::checkDerivedTimes).
constexpr uint32_t kSampleSumBytes = kHeaderBytes + uint32_t(kSampleValues) * kValueBytes;
// The fewest cells a sum keeps to carry the sides: on a longer column
// (more than 42 boxes) the faces would leave it fewer, and it goes without
// the sides. On 64x2x1 from the object median, a sum of 21 cells with the
// sides moved one of the two columns, in chains of slabs, and made the
// frame 2.57 times the unbalanced one (1.79 without the sides; with one
// cell, when the faces beside took a second value a box, 6.4).
constexpr int kSampleMinCells = 29;
// Without sides, the boxes' passes go up in at most this many groups of
// neighbouring boxes (ColumnSample::groupBoxes), in the message's room: on
// 64x1x1 a pass a box (1.5 KB a hop) held the rays behind the sum, and the
// built-in scene's frame lost 3 to 5 % against its start held.
constexpr int kSampleGroups = 8;
bool sidesFit(int columnLength);

// Where inner face i stands among `passes` (ColumnSample::passes): within a
// group, as if its boxes were of even length; past the last, the top.
double faceAmong(const std::vector<BoxPass>& passes, int i);

// A column's sample as the gather carries it up: the work (ps) in cells
// along the axis, each spread evenly over its cell; in the same cells, what
// its rays across the column's sides, to or from the columns beside, would
// cost a node to pass on along the axis, once (`side`); the column's inner
// faces as they stand; the most work any one node's box of the column held
// (what the frame would take, times the sample's share, with the boxes as
// they stand); and when the column's lowest node sent it up (how long it
// took to climb the column); and, per box, what passing all its objects on
// to a neighbour would cost (ps: the slab handover's handling and grid
// updates and the objects' time on the wire; for the price of a move).
struct ColumnSample {
    std::vector<double> edges;  // K + 1, increasing
    std::vector<double> mass;   // K
    std::vector<double> side;   // K
    std::vector<double> faces;  // the inner faces below the last node added
    std::vector<double> moves;  // per box added: what passing its objects on costs (ps)
    // Without sides, the boxes in each entry of `moves`, whose edges are
    // then `faces` (groupBoxes); with sides, empty: an entry a box.
    std::vector<double> boxes;
    bool sides = false;  // the column has columns beside it: the sum carries the faces and the sides
    // With crossings (--sample-links on): per cell, the sample's ray
    // segments along the axis that begin there (+1) and end there (-1):
    // their sum below an edge is how many of them cross it, each a ray on
    // the link a plane there would put between its boxes. `crossOver`:
    // those that end past the last box added, through its upper face (they
    // go on in the next box's first cell). Why: the sample's work does not
    // show a link's load, and a plane moved towards the eye leaves more of
    // the column's rays on the first box's link, whatever the work
    // (doc/balancing.md, "The recommended policy": 1.215 of the unbalanced
    // frame, the first box's link 97 % busy).
    bool crossings = false;
    std::vector<double> cross;  // K
    double crossOver = 0;
    double wirePs = 0;  // (the top node, as it decides; not carried) a ray's time on the column's link, in ps
    double busiestBox = 0;
    double startedAt = 0;  // ps into the frame
    // A node's bins over its box [lo, hi], above the cells so far (lo the
    // last edge), and what passing its objects on would cost.
    void add(double lo, double hi, const std::vector<double>& bins, const std::vector<double>& sideBins = {},
             double passPs = 0, const std::vector<double>& crossBins = {});
    // With crossings: how many of the sample's rays cross x along the axis.
    double crossingsAt(double x) const;
    // At most `cells` cells: each then an equal share of the work.
    void compress(int cells);
    // Without sides, at most `most` entries of `moves`: neighbouring ones
    // merged, the pair of fewest boxes first, their face between dropped.
    void groupBoxes(int most);
    // The entries of `moves`, each over its boxes along the axis.
    std::vector<BoxPass> passes() const;
    // Where the column's inner face i stands (between its boxes i and
    // i + 1): within a group, as if its boxes were of even length.
    double faceAt(int i) const;  // (faceAmong of passes())
    // The most cells whose values() are at most `values` long (at least 1).
    int cellsWithin(int values) const;
    // For a message: busiestBox, startedAt, whether it has sides, the
    // number of faces, the faces, the boxes' moves, the edges, the masses,
    // the sides' (only with sides).
    std::vector<double> values() const;
    static ColumnSample of(const std::vector<double>& values);  // (empty if they are not a sample)
    double within(double a, double b) const;
    double sideWithin(double a, double b) const;
    // The coordinate c >= from where [from, c] holds `work`; `limit` if [from, limit] holds less.
    double cut(double from, double limit, double work) const;
    double total() const;
    double lo() const { return edges.empty() ? 0 : edges.front(); }
    double hi() const { return edges.empty() ? 0 : edges.back(); }
    bool wellFormed() const;  // edges increasing, one more than the masses, as many sides, none negative

private:
    static double below(const std::vector<double>& e, const std::vector<double>& m, double x);  // of m in cells e, below x
};

// The column's count - 1 inner planes that split the work of `column` so
// that the dearest part is as cheap as it can be, each part at least
// minThickness thick, the slack shared evenly; empty if no work was
// recorded.
std::vector<double> splitBySample(const ColumnSample& column, int count, double minThickness);
// The work of the dearest part between `planes` (the column's ends outside them).
double dearestPart(const ColumnSample& column, const std::vector<double>& planes);
// The same, each part with the passes its planes would cause against the
// planes of the columns beside (`beside`: each column's, as it proposes to
// move or holds). A ray that crosses the column's side arrives at the node
// of the sender's index, which passes it on along the axis to the owner,
// through every node between: each of them handles it once. The sum does
// not say which side a crossing was on: each column beside counts for an
// even share of them. (Without columns beside, or where their planes are
// not known, every crossing counts one pass in its own part.)
double dearestPartWithPasses(const ColumnSample& column, const std::vector<double>& planes,
                             const std::vector<std::vector<double>>& beside);
// What holding costs by the sample: the busiest box's work, or the dearest
// part of the faces as they stand with the passes they cause against the
// planes beside, if dearer.
double holdingPart(const ColumnSample& column, const std::vector<std::vector<double>>& beside);

// How long moving the column's faces to `planes` takes (ps): the longest
// chain of slab handovers, each face's (move_forecast.h, chainPs), with
// `hopPs` a handover's latency and handling, and the objects each box
// passes on (`moves`). The nodes on a chain wait for their faces. On a
// long column from the uniform split the whole sample moved every face
// (balls-5 on 64x2x1: 1,886 slides in chains along 64 boxes), and the
// frame took 6.5 times the unbalanced one, nearly all of it the chains.
double sampleMovePs(const ColumnSample& column, const std::vector<double>& planes, double hopPs);

// Whether moving to planes whose dearest part holds `dearest` of the sample
// (passes included: dearestPartWithPasses) pays against holding, whose
// dearest part holds `hold` (holdingPart), decided `elapsed` into the
// frame: the frame at the boxes as they stand takes about the sample's
// share times `hold`, and what is left of it once the faces have moved
// shrinks by dearest / hold, less the move's own time (`movePs`:
// sampleMovePs); the move must save kSampleMinGain of that frame. The planes are counted in place as long after the decision as
// the sum took to climb the column (they go down the same links; counted
// at the decision alone, moves came down too late on long columns:
// doc/history.md). (A 64-long column of 1 GB/s links gathers for about as
// long as the whole frame takes: moving then only costs.)
constexpr double kSampleMinGain = 0.04;
bool samplePays(const ColumnSample& column, double hold, double dearest, double elapsed, double movePs = 0);

}  // namespace rt
