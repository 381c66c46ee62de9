// The next frame's time, forecast from the frame before for any planes
// along the axis, and the planes that make it shortest: `resplit`'s and
// `measured`'s choice between frames (doc/balancing.md, "Between frames").
//
// From what the frame before left behind (frame_state.h) it takes, per column: the tracing
// work by where it happened (work_by_position), the rays a plane would cut
// at each position, in each direction (cuts_up, cuts_down), what a node
// spends on a ray across a face (face_handling_ns / face_crossings), and
// the rays sent to each neighbouring column by where they left (lateral);
// and the wire time per ray on the links. For planes P it forecasts
//  - each node's busy time: the work between its planes, the rays its
//    planes cut at the handling cost, and the rays it passes on untraced
//    (a ray that crosses into a column whose planes differ is handed to the
//    node of its sender's index, which passes it along the axis to the
//    owner; each pass a receive and a send). Where the box measured had
//    one grid cell along the axis, a ray running across the axis inside it
//    tested every object across the box: those tests (work_by_position.
//    within) grow with the thickness twice over, in the rays and in the
//    objects each tests, and are scaled by the new box's cell along the
//    axis over the old (sphere tests x100, across the axis, N = 8: a box
//    that grew 0.0102 to 0.0142 thick did 2.1 times the sphere tests);
//  - each link's rays: the cuts at its plane, the rays sent across columns
//    by the sender's owner, and the passes;
// and the frame as the dearer of the busiest node and the busiest link,
// or kTandem times the cheaper where the two are closer than that: a link
// busy almost as long as the busiest node queues the rays behind it, and
// the nodes after it get them late (modern, across, N = 4: busiest node
// 732 us, busiest link 715 us, frame 785 us; with the last plane moved so
// that the link is 648 us, frame 736 us). The frames measured are within a
// few per cent of this, at default links and past the knee alike.
#pragma once
#include <vector>

#include "balance/frame_state.h"
#include "config/machine_config.h"
#include "base/mesh_geometry.h"
#include "balance/minimax_split.h"
#include "shape.h"

namespace rt {

// Per column (ColumnGeometry order): its N - 1 inner planes along the axis.
using InnerPlanes = std::vector<std::vector<double>>;

// How much longer than the cheaper of the busiest node and the busiest link
// a frame is where the two are close (the forecast's frame: the dearer, or
// this times the cheaper): a node and a link that both work near all of the
// frame wait for each other. Fitted on frames measured (doc/balancing.md,
// "Between frames").
constexpr double kTandem = 1.1;

// How many times the tests of a ray running across the axis inside a box
// grow when the box goes from `measured` thick, with one grid cell along
// the axis, to `thickness`: its cell along the axis over the old one.
double oneCellGrowth(double thickness, double measured);

// Where a box's grid would have cells more than this many times the size
// (edge over edge) of a measured grid it takes objects from, the forecast
// counts that grid's work there as grown (FrameForecast::coarsening). A box
// that takes in a crowd beside a wide object (the SPD balls' floor, along
// z) spreads its grid over the wide object's span: on balls-4 on the 1987
// machine at 128x128, 4x4x4, along z, `measured` gave the bottom box the
// lower half of the sphere flake, its cells grew 4.1 times and its sphere
// tests 8 times (4.1^1.5 = 8.3), and the frame took 1.60 of the unbalanced
// one where the forecast said 0.31. From 2 times, moves that gained were
// refused: along x on balls-4 at N = 5, 1 GB/s, a box that took in the
// floor's end grew its cells 2.1 times, and the steady state went from
// 0.281 to 0.315 of the unbalanced frame.
constexpr double kCoarser = 3;

class FrameForecast {
public:
    // From frame `r` (of this mesh and axis: the caller checks) and the
    // planes as they stood on average over it.
    // With the scene's `objects`, a part whose grid would be coarser than
    // the ones measured there counts it (kCoarser); without, it does not.
    FrameForecast(const FrameState& r, const MachineConfig& m, const InnerPlanes& averaged,
                  const std::vector<Shape>* objects = nullptr);

    struct Forecast {
        double frameNs = 0;  // the dearer of the two below
        double nodeNs = 0;   // the busiest node's busy time
        double linkNs = 0;   // the busiest link's wire time
        double passes = 0;   // rays passed on untraced
    };
    // With `startNs` (per column, per node: when it can start, ns: its
    // faces in place after a move, facesInPlaceNs), the busiest node is the
    // one that ends last: a node that waits for its faces renders the
    // frame's work after them, and one already in place renders meanwhile.
    Forecast forecast(const InnerPlanes& planes, const InnerPlanes* startNs = nullptr) const;

    // The planes of least forecast busy time for the busiest node, each
    // column on its own (rays crossing columns are passed on where they
    // differ), and one set for all columns (no ray is passed on). splits():
    // both at once, each part's cost worked out once.
    InnerPlanes perColumn() const { return splits().perColumn; }
    InnerPlanes aligned() const { return splits().aligned; }
    struct Splits {
        InnerPlanes perColumn, aligned;
    };
    Splits splits() const;

private:
    struct Column {
        std::vector<double> below;     // work below each grid edge (ns), G + 1 entries
        std::vector<double> up, down;  // rays a plane at each grid edge cuts, going up and down the axis
        double perCrossing = 0;        // ns a node spends on one ray across a face along the axis
        std::vector<double> perBin;    // (while reading: work per bin)
        double faceNs = 0, faceRays = 0;
        // The boxes measured whose grid had one cell along the axis, [from,
        // to) in bins, and the tests of segments within them below each
        // grid edge (G + 1 entries; while reading, per bin).
        std::vector<std::pair<int, int>> oneCell;
        std::vector<double> withinBelow;
        // Rays its nodes sent to each neighbouring column, below each grid
        // edge (G + 1 entries each): a node's link to its neighbour there
        // carries those of its part (the neighbour's node of its index).
        std::vector<std::vector<double>> lateralBelow;
        Box box;                     // over the whole axis
        std::vector<Shape> objects;  // in it (with the scene's objects, where a grid was measured)
        // Each node's grid as the frame ended (the part it covered, the
        // object centres there, its cell's size: the cube root of a cell's
        // volume) and its tracing work below each bin edge from bin
        // `first` on.
        struct Grid {
            size_t centres = 0;  // of the column's objects, in its span
            Box span;
            double cell = 0;
            int first = 0;
            std::vector<double> below;
        };
        std::vector<Grid> grids;
    };
    struct Lateral {
        int from, to, bin;  // columns; the bin it left from
        double rays;
    };
    double readNode(const NodeFrameState& node, const InnerPlanes& averaged);
    void readGrid(Column& c, const NodeFrameState& node);
    void readObjects(const FrameState& r, const std::vector<Shape>& objects);
    double work(const Column& c, int i, int j) const;  // forecast busy between edges i < j, passes aside
    double coarsening(const Column& c, int i, int j) const;  // what a coarser grid there adds to it (kCoarser)
    double partCost(const Column& c, int i, int j) const;  // what the searches minimise the largest of
    int edgeOf(double x) const;
    int ownerOf(const std::vector<double>& planes, double x) const;  // the node index along the column
    std::vector<double> planesOf(const std::vector<int>& edges) const;
    // The search on `grid`'s cells (grid edges in bins) with these part costs: its planes.
    std::vector<double> searchOn(const std::vector<int>& grid, const PartCosts& pc) const;
    std::vector<int> gridEdges() const;  // the coarse grid the search runs on (bins at every edge)
    int minCells(int step) const;

    ColumnGeometry g_;
    int n_ = 1, bins_ = 1;
    double lo_ = 0, hi_ = 1, minBins_ = 0;
    std::vector<Column> columns_;
    std::vector<Lateral> lateral_;
    double wirePerRay_ = 0;  // ns
    double linkWeight_ = 1;  // a part's wire time in the searches: kTandem where a node set the frame measured
    double margin_ = 0;      // the world's rounding margin (objects in a box: region.h)
};

}  // namespace rt
