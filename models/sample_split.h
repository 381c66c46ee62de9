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
#include <cstdint>
#include <vector>

namespace rt {

// The sample: the pixels on every kSampleSide-th row and column, one in 16.
// A regular pattern, not a random one: on the paper's machine (N = 4 to 8,
// f = 1/N, both views) a random 1/16 of the pixels put the planes where a
// whole frame took 1.3 times as long as with the pattern's at N = 8, and
// 1/25 or 1/64 of the pixels were worse again (doc/balancing.md).
constexpr uint32_t kSampleSide = 4;
bool inSample(uint32_t pixel, uint32_t width);

// A node records its sample's work in this many equal bins over its box
// (which holds still while it samples): finer where the boxes are thin, as
// where the objects crowd, at 8 bytes a bin in the gather's messages.
constexpr int kSampleBins = 64;

// A column's sample as the gather carries it up: for each node from the
// lowest, its box's extent along the axis and its bins.
struct ColumnSample {
    std::vector<double> values;  // per node: lo, hi, then kSampleBins bins of work (ps)
    void add(double lo, double hi, const std::vector<double>& bins);
    // The work between a and b (work inside a bin taken as spread evenly over it).
    double within(double a, double b) const;
    // The coordinate c >= from where [from, c] holds `work`; `limit` if [from, limit] holds less.
    double cut(double from, double limit, double work) const;
    double total() const;
    double lo() const { return values.empty() ? 0 : values[0]; }
    double hi() const { return values.empty() ? 0 : values[values.size() - kSampleBins - 1]; }
    bool wellFormed() const;  // whole nodes, each box in order, meeting the last, and no bin negative

private:
    double below(double x) const;  // the work below x
};

// The column's count - 1 inner planes that split the work of `column` so
// that the dearest part is as cheap as it can be, each part at least
// minThickness thick, the slack shared evenly; empty if no work was
// recorded.
std::vector<double> splitBySample(const ColumnSample& column, int count, double minThickness);

}  // namespace rt
