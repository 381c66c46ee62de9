// The split of a line of grid cells into parts whose dearest part is as
// cheap as it can be: `resplit`'s planes (frame_forecast.h), where what a
// part costs is not the sum of its cells (a plane adds the rays it cuts).
// Plain C++.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rt {

// A part's cost from grid edge i to grid edge j (i < j), in a (m + 1) x
// (m + 1) matrix by its end j (the search reads the parts that end at one
// edge, in a row); entries with i >= j are not read.
struct PartCosts {
    int m = 0;
    std::vector<double> cost;
    double operator()(int i, int j) const { return cost[size_t(j) * size_t(m + 1) + size_t(i)]; }
    double& at(int i, int j) { return cost[size_t(j) * size_t(m + 1) + size_t(i)]; }
};

// Edges 0 = e_0 < e_1 < ... < e_count = m, each part at least `minCells`
// wide, that minimise the dearest part; among those, the sum of the parts'
// squared costs (the slack goes to the other parts evenly rather than to
// one). Returns the count + 1 edges. Throws std::invalid_argument when
// count parts of minCells do not fit in m cells.
std::vector<int> minimaxSplit(const PartCosts& c, int count, int minCells);

}  // namespace rt
