// `resplit` between frames (doc/balancing.md, "Between frames"): each
// column's boundaries move to the quantiles of the busy time its nodes had
// in the frame before, each node's busy time taken as spread evenly over
// its box. A running machine renders frame after frame of a slowly changing
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

// The time-weighted mean position of a boundary over [0, end]: `history`
// holds (time, position) from time 0 on, in time order.
double timeAveraged(const std::vector<std::pair<double, double>>& history, double end);

}  // namespace rt
