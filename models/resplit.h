// `resplit` between frames (doc/balancing.md, "Between frames"): each
// column's boundaries move to the quantiles of the busy time its nodes had
// in the frame before, placed where it happened: the tracing work by where
// along the axis each step was (the nodes' work profiles), the rest of each
// node's busy time spread evenly over its box. A running machine renders frame after frame of a slowly changing
// view, so the last frame's measured work is the best forecast of the next
// one's; the within-frame policies chase the wave of primary rays instead.
#pragma once
#include <utility>
#include <vector>

namespace rt {

// `edges`: a column's N + 1 planes along the axis (the world's ends
// included) as they stood over the frame; `busy`: each of its N nodes' busy
// time. Returns the N - 1 inner planes that give each node an equal share of
// the column's busy time, every box at least `minThickness` thick. With no
// busy time, the planes stay.
std::vector<double> resplitPlanes(const std::vector<double>& edges, const std::vector<double>& busy, double minThickness);

// A piece of a column's work: `work` spread evenly over [from, to] along the axis.
struct WorkPiece {
    double from, to, work;
};

// The same from pieces that may overlap (a node's box and the profile's
// bins within it): the `count` - 1 inner planes in [lo, hi] at which the
// work below reaches k / count of the whole, every box at least
// `minThickness` thick; with no work, `fallback` (the planes as they are).
std::vector<double> resplitPlanes(const std::vector<WorkPiece>& pieces, double lo, double hi, int count,
                                  double minThickness, const std::vector<double>& fallback);

// The time-weighted mean position of a boundary over [0, end]: `history`
// holds (time, position) from time 0 on, in time order.
double timeAveraged(const std::vector<std::pair<double, double>>& history, double end);

}  // namespace rt
