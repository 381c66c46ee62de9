// What a frame leaves behind for the next one's planes (doc/balancing.md,
// "Between frames"): the boxes as they ended, where along the axis each
// node's work happened, the rays its faces cut, the boundaries' histories,
// and the few figures of the links the forecast takes. A value: the machine
// makes it at the end of a frame (machine/frame_state_of.h), the report
// serialises it (analysis/report.cpp), and a report read back at the user's
// edge (--boundaries-from) gives it again (tb/frame_state_json.h), to the bit.
// Times in ns, as the report has them.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "base/mesh_geometry.h"
#include "box.h"

namespace rt {

// Values in bins fixed in the world along the axis (work_by_position.h):
// value k is of bin firstBin + k.
struct Binned {
    int64_t firstBin = 0;
    std::vector<double> values;
};

// Where along the axis a node's work happened over the frame, in bins
// axisFrom + [k, k + 1) x binWidth.
struct WorkAlongAxis {
    double axisFrom = 0, binWidth = 0;
    Binned ns;                    // its tracing work, less its handling of rays across its faces along the axis
    std::optional<Binned> within;  // of it, tests of segments that neither entered nor left by such a face
    double faceHandlingNs = 0;    // that handling
    uint64_t faceCrossings = 0;   // of that many crossings
    // How many traced segments a plane would cut, going up the axis and
    // down it: value k at the upper edge of bin firstBin + k.
    std::array<Binned, 2> cuts;
    // Rays sent to each neighbouring column, by the bin they left from, per
    // link direction (dirOf; along the axis: none).
    std::array<std::optional<Binned>, 6> lateral;
};

struct NodeFrameState {
    Cell cell{};
    Box box;        // as the frame ended it
    size_t objects = 0;
    double objectBytes = 0;  // theirs on a link, summed (0: not known, a sphere's each: move_forecast.h)
    std::optional<std::array<int, 3>> gridCells;  // its grid's cells per axis, if it holds objects
    std::optional<Box> gridSpan;                  // and the part of its box the grid covers (UniformGrid::occupiedPart)
    double busyNs = 0;
    std::optional<WorkAlongAxis> work;  // if it traced anything
};

// One boundary between nodes index-1 and index of a column along the axis:
// (time in ns, position) from the frame's start, in time order.
struct BoundaryState {
    std::array<int, 2> column{};  // the column's coordinates on the other two axes (in axis order)
    int index = 0;
    std::vector<std::pair<double, double>> history;
};

struct FrameState {
    std::array<int, 3> dims{};  // the mesh it ran on
    int axis = 0;               // and its progress axis
    double renderTimeNs = 0;
    std::vector<NodeFrameState> nodes;
    std::vector<BoundaryState> boundaries;
    uint64_t raysPassed = 0;      // rays sent on untraced, all nodes
    double rayWireNs = 0;         // the rays' wire time on the links between nodes
    double busiestLinkWireNs = 0;  // the busiest such link's wire busy time
};

}  // namespace rt
