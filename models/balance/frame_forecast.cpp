#include "balance/frame_forecast.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <tuple>

#include "balance/minimax_split.h"
#include "balance/plane_spacing.h"
#include "balance/work_by_position.h"
#include "grid.h"
#include "lattice.h"
#include "region.h"

namespace rt {
namespace {

// What the searches may cost between two frames: about 10^8 part costs.
constexpr double kSearchBudget = 1e8;
constexpr int kMaxGrid = 512;

// `v` spread evenly over [a, b] into bins of width w from lo (a point if b <= a).
void spread(std::vector<double>& bins, double lo, double w, double a, double b, double v) {
    const int last = int(bins.size()) - 1;
    auto binOf = [&](double x) { return std::clamp(int(std::floor((x - lo) / w)), 0, last); };
    if (!(b > a)) {
        bins[size_t(binOf(a))] += v;
        return;
    }
    for (int k = binOf(a); k <= binOf(b); ++k) {
        const double from = std::max(a, lo + k * w), to = std::min(b, lo + (k + 1) * w);
        if (to > from) bins[size_t(k)] += v * (to - from) / (b - a);
    }
}

double volumeOf(const Box& b) {
    double v = 1;
    for (int a = 0; a < 3; ++a) v *= std::max(b.extent()[a], 1e-300);
    return v;
}

size_t centresIn(const std::vector<Shape>& objects, const Box& b) {
    size_t n = 0;
    for (const Shape& o : objects) {
        const Box ob = o.bounds();
        const Vec3 m = 0.5 * (ob.lo + ob.hi);
        n += (m.x >= b.lo.x && m.x <= b.hi.x && m.y >= b.lo.y && m.y <= b.hi.y && m.z >= b.lo.z && m.z <= b.hi.z) ? 1 : 0;
    }
    return n;
}

// A grid's cell size over `part`: the cube root of a cell's volume.
double cellSize(const Box& part, const std::array<int, 3>& cells) {
    double v = 1;
    for (int a = 0; a < 3; ++a) v *= std::max(part.extent()[a] / cells[size_t(a)], 1e-300);
    return std::cbrt(v);
}

// (FrameForecast::coarsening)
constexpr size_t kLeastKept = 8;

}  // namespace

FrameForecast::FrameForecast(const FrameState& r, const MachineConfig& m, const InnerPlanes& averaged,
                             const std::vector<Shape>* objects)
    : g_(m.balance.axis, m.dims), n_(g_.length()), bins_(WorkByPosition::kBinsPerBox * g_.length()) {
    const int ax = g_.axis;
    lo_ = 1e300;
    hi_ = -1e300;
    for (const NodeFrameState& node : r.nodes) {
        lo_ = std::min(lo_, node.box.lo[ax]);
        hi_ = std::max(hi_, node.box.hi[ax]);
    }
    if (!(hi_ > lo_)) throw std::runtime_error("a frame whose boxes span nothing along the axis");
    minBins_ = m.balance.minThickness * WorkByPosition::kBinsPerBox;
    columns_.assign(size_t(g_.count()), Column{});
    for (Column& c : columns_) {
        c.perBin.assign(size_t(bins_), 0.0);
        c.withinBelow.assign(size_t(bins_), 0.0);
        c.up = c.down = std::vector<double>(size_t(bins_ + 1), 0.0);
    }
    double raysOnLinks = 0;
    for (const NodeFrameState& node : r.nodes) raysOnLinks += readNode(node, averaged);
    if (objects) readObjects(r, *objects);
    for (Column& c : columns_) {
        c.below.assign(size_t(bins_ + 1), 0.0);
        for (int k = 0; k < bins_; ++k) c.below[size_t(k + 1)] = c.below[size_t(k)] + c.perBin[size_t(k)];
        c.perBin = {};
        std::sort(c.oneCell.begin(), c.oneCell.end());  // (disjoint boxes: in order along the column)
        c.withinBelow.insert(c.withinBelow.begin(), 0.0);  // per bin to below each edge
        for (int k = 0; k < bins_; ++k) c.withinBelow[size_t(k + 1)] += c.withinBelow[size_t(k)];
        c.perCrossing = c.faceRays > 0 ? c.faceNs / c.faceRays : 0;
    }
    std::map<std::pair<int, int>, std::vector<double>> lateral;  // (from, to) column: rays by bin
    for (const Lateral& l : lateral_) {
        std::vector<double>& v = lateral[{l.from, l.to}];
        if (v.empty()) v.assign(size_t(bins_), 0.0);
        v[size_t(l.bin)] += l.rays;
    }
    for (const auto& [key, v] : lateral) {
        std::vector<double> below(size_t(bins_ + 1), 0.0);
        for (int k = 0; k < bins_; ++k) below[size_t(k + 1)] = below[size_t(k)] + v[size_t(k)];
        columns_[size_t(key.first)].lateralBelow.push_back(std::move(below));
    }
    raysOnLinks += double(r.raysPassed);
    double busiestNode = 0;
    for (const NodeFrameState& node : r.nodes) busiestNode = std::max(busiestNode, node.busyNs);
    wirePerRay_ = raysOnLinks > 0 ? r.rayWireNs / raysOnLinks : 0;
    const double busiestLink = r.busiestLinkWireNs;
    // Where a node set the frame, the searches keep the links below it by
    // the tandem margin (Forecast::frameNs); where a link did, as before.
    linkWeight_ = busiestNode >= busiestLink ? kTandem : 1.0;
}

// One node's part of the frame into its column; returns the rays it put on links.
double FrameForecast::readNode(const NodeFrameState& node, const InnerPlanes& averaged) {
    const Cell cell = node.cell;
    const size_t col = size_t(g_.columnOf(cell));
    Column& c = columns_.at(col);
    const int k = cell[size_t(g_.axis)];
    const double w = (hi_ - lo_) / bins_;
    double rest = node.busyNs, rays = 0;
    // The box as it stood on average over the frame.
    const std::vector<double>& planes = averaged.at(col);
    const double boxLo = k == 0 ? lo_ : planes.at(size_t(k - 1)), boxHi = k == n_ - 1 ? hi_ : planes.at(size_t(k));
    if (node.work) {
        const WorkAlongAxis& p = *node.work;
        const double from = p.axisFrom, width = p.binWidth;
        const bool oneCell = node.gridCells && (*node.gridCells)[size_t(g_.axis)] == 1;
        if (oneCell && p.within && edgeOf(boxHi) > edgeOf(boxLo)) {
            c.oneCell.push_back({edgeOf(boxLo), edgeOf(boxHi)});
            double bin = double(p.within->firstBin);
            for (double v : p.within->values) {
                spread(c.withinBelow, lo_, w, from + bin * width, from + (bin + 1) * width, v);
                ++bin;
            }
        }
        double b = double(p.ns.firstBin);
        for (double v : p.ns.values) {
            spread(c.perBin, lo_, w, from + b * width, from + (b + 1) * width, v);
            rest -= v;
            ++b;
        }
        if (node.gridCells && node.gridSpan && node.objects > 0 && !p.ns.values.empty()) readGrid(c, node);
        rest -= p.faceHandlingNs;
        c.faceNs += p.faceHandlingNs;
        c.faceRays += double(p.faceCrossings);
        rays += double(p.faceCrossings) / 2;  // (each crossing is counted by both its nodes)
        for (int up = 0; up < 2; ++up) {
            std::vector<double>& cuts = up == 0 ? c.up : c.down;
            double e = double(p.cuts[size_t(up)].firstBin) + 1;  // each count stands at its bin's upper edge
            for (double v : p.cuts[size_t(up)].values) {
                const int edge = int(std::lround((from + e * width - lo_) / w));
                if (edge > 0 && edge < bins_) cuts[size_t(edge)] += v;
                ++e;
            }
        }
        for (int d = 0; d < 6; ++d) {
            if (!p.lateral[size_t(d)]) continue;
            const Cell to = neighbour(cell, d);
            double b2 = double(p.lateral[size_t(d)]->firstBin);
            for (double n : p.lateral[size_t(d)]->values) {
                const double x = from + (b2 + 0.5) * width;
                ++b2;
                if (!(n > 0) || !inMesh(to, g_.dims)) continue;
                rays += n;
                lateral_.push_back({int(col), g_.columnOf(to), std::clamp(int(std::floor((x - lo_) / w)), 0, bins_ - 1), n});
            }
        }
    }
    // The rest (rays passed on, balancing) over the box.
    spread(c.perBin, lo_, w, boxLo, boxHi, std::max(0.0, rest));
    return rays;
}

double FrameForecast::work(const Column& c, int i, int j) const {
    auto cut = [&](int e) { return e > 0 && e < bins_ ? c.up[size_t(e)] + c.down[size_t(e)] : 0.0; };
    double w = c.below[size_t(j)] - c.below[size_t(i)] + c.perCrossing * (cut(i) + cut(j));
    // The one-cell boxes the part overlaps (the searches ask for every part:
    // a few boxes each, found by bisection, not all of the column's).
    auto box = std::partition_point(c.oneCell.begin(), c.oneCell.end(), [&](const std::pair<int, int>& x) { return x.second <= i; });
    for (; box != c.oneCell.end() && box->first < j; ++box) {
        const auto [from, to] = *box;
        const int a = std::max(i, from), b = std::min(j, to);
        w += (c.withinBelow[size_t(b)] - c.withinBelow[size_t(a)]) * (oneCellGrowth(j - i, to - from) - 1);
    }
    return w;
}

// Each column's box over the whole axis and the objects in it, for the
// grids its parts would build (coarsening).
void FrameForecast::readObjects(const FrameState& r, const std::vector<Shape>& objects) {
    Box world;
    for (const NodeFrameState& node : r.nodes) world.add(node.box);
    margin_ = roundingMargin(world);
    // (binned once, as the machine bins the scene for its boxes: each
    // column looks among a few cells' objects, not the whole scene's)
    const ObjectBins bins(objects, Lattice::uniform(world, g_.dims), margin_);
    std::vector<bool> seen(columns_.size(), false);
    for (const NodeFrameState& node : r.nodes) {
        const size_t col = size_t(g_.columnOf(node.cell));
        if (seen[col]) continue;
        seen[col] = true;
        Column& c = columns_[col];
        c.box = node.box;
        c.box.lo[g_.axis] = lo_;
        c.box.hi[g_.axis] = hi_;
        if (c.grids.empty()) continue;  // (none measured: no grid grows)
        c.objects = bins.overlapping(c.box);
        for (Column::Grid& g : c.grids) g.centres = centresIn(c.objects, g.span);
    }
}

void FrameForecast::readGrid(Column& c, const NodeFrameState& node) {
    const WorkAlongAxis& p = *node.work;
    const double w = (hi_ - lo_) / bins_;
    const double a = p.axisFrom + double(p.ns.firstBin) * p.binWidth;
    const double z = a + double(p.ns.values.size()) * p.binWidth;
    Column::Grid g{0, *node.gridSpan, cellSize(*node.gridSpan, *node.gridCells), 0, {}};
    g.first = std::clamp(int(std::floor((a - lo_) / w)), 0, bins_ - 1);
    const int last = std::clamp(int(std::floor((z - lo_) / w)), g.first, bins_ - 1);
    std::vector<double> perBin(size_t(last - g.first + 1), 0.0);
    double b = double(p.ns.firstBin);
    for (double v : p.ns.values) {
        spread(perBin, lo_ + g.first * w, w, p.axisFrom + b * p.binWidth, p.axisFrom + (b + 1) * p.binWidth, v);
        ++b;
    }
    g.below.assign(perBin.size() + 1, 0.0);
    for (size_t k = 0; k < perBin.size(); ++k) g.below[k + 1] = g.below[k] + perBin[k];
    c.grids.push_back(std::move(g));
}

// The part's grid as a node would build it over the column's box there
// (its objects: UniformGrid's occupied part and resolution rule), against
// each measured grid it overlaps whose cells it makes more than kCoarser
// times the size: a ray crossing that grid's objects in cells r times the
// size walks 1/r the cells, each holding r^3 times the objects at the same
// density, and that grid's work in the part grows r^1.5 times (measured:
// balls-4 along z, kCoarser), times the density of object centres the part
// keeps of it over the grid's own (a part that takes in a sliver of a crowd
// keeps few: at the edge of Fig. 4's crowd, boxes of 1 to 11 spheres grew
// their cells 3 times, at a tenth of the density). Only where the part
// keeps kLeastKept of that grid's object centres or more: from fewer the density
// is a guess, and so is what their tests add (at the far end of Fig. 4's
// crowd, sphere tests x100, across the axis, N = 6: 3 spheres, their
// density 1.14 times the grid's, a growth of 3.6 counted, and a move that
// made the steady state 1.5 % faster refused). From 8 on, not more: on
// balls-2 along z (modern machine, 4x4x4) the bottom box took 9 of the 13
// spheres of the box above, its grid 4.2 times coarser, and its sphere
// tests grew 5.4 times (frame 2 at 128x128: 1.317 of the unbalanced frame
// while the least was 64).
double FrameForecast::coarsening(const Column& c, int i, int j) const {
    if (c.objects.empty()) return 0;
    const int ax = g_.axis;
    const double w = (hi_ - lo_) / bins_;
    Box box = c.box;
    box.lo[ax] = i == 0 ? lo_ : lo_ + i * w;
    box.hi[ax] = j == bins_ ? hi_ : lo_ + j * w;
    const std::vector<Shape> objects = objectsOverlapping(c.objects, box, margin_);
    if (objects.empty()) return 0;
    const Box part = UniformGrid::occupiedPart(objects, box);
    const double cell = cellSize(part, UniformGrid::resolution(part, objects.size()));
    double extra = 0;
    for (const Column::Grid& g : c.grids) {
        Box shared = g.span;  // (of the grid's span, the part in the box)
        shared.lo[ax] = std::max(box.lo[ax], g.span.lo[ax]);
        shared.hi[ax] = std::min(box.hi[ax], g.span.hi[ax]);
        const double r = cell / g.cell;
        // (not a sliver of a bin, where a plane rounds to the bin's edge)
        if (!(shared.hi[ax] - shared.lo[ax] > w) || !(r > kCoarser) || g.centres == 0) continue;
        const size_t kept = centresIn(objects, shared);
        if (kept < kLeastKept) continue;
        const double density = double(kept) / volumeOf(shared) / (double(g.centres) / volumeOf(g.span));
        const double growth = std::pow(r, 1.5) * density;
        if (!(growth > 1)) continue;
        const int n = int(g.below.size()) - 1;
        const int from = std::clamp(i - g.first, 0, n), to = std::clamp(j - g.first, 0, n);
        extra += (g.below[size_t(to)] - g.below[size_t(from)]) * (growth - 1);
    }
    return extra;
}

double oneCellGrowth(double thickness, double measured) {
    // The grid's cells per unit length along the axis stay about 1 /
    // measured as a box grows (objects grow with its volume): round(t /
    // measured) cells, at least one.
    const double cells = std::max(1.0, std::round(thickness / measured));
    return thickness / cells / measured;
}

double FrameForecast::partCost(const Column& c, int i, int j) const {
    // The node's busy time, or the wire time of the busier link through its
    // upper plane, or of its busiest link to a neighbouring column (the
    // rays it sends there: more, the longer its part).
    double rays = j < bins_ ? std::max(c.up[size_t(j)], c.down[size_t(j)]) : 0.0;
    for (const std::vector<double>& below : c.lateralBelow) rays = std::max(rays, below[size_t(j)] - below[size_t(i)]);
    return std::max(work(c, i, j), linkWeight_ * wirePerRay_ * rays);
}

int FrameForecast::edgeOf(double x) const {
    return std::clamp(int(std::lround((x - lo_) / (hi_ - lo_) * bins_)), 0, bins_);
}

int FrameForecast::ownerOf(const std::vector<double>& planes, double x) const {
    return int(std::upper_bound(planes.begin(), planes.end(), x) - planes.begin());
}

FrameForecast::Forecast FrameForecast::forecast(const InnerPlanes& planes, const InnerPlanes* startNs) const {
    if (planes.size() != columns_.size()) throw std::invalid_argument("forecast: planes for another mesh");
    Forecast f;
    std::vector<std::vector<double>> busy(columns_.size()), up(columns_.size()), down(columns_.size());
    for (size_t c = 0; c < columns_.size(); ++c) {
        std::vector<int> e{0};
        for (double x : planes[c]) e.push_back(edgeOf(x));
        e.push_back(bins_);
        for (size_t k = 0; k + 1 < e.size(); ++k)
            busy[c].push_back(work(columns_[c], e[k], e[k + 1]) + coarsening(columns_[c], e[k], e[k + 1]));
        for (size_t k = 1; k + 1 < e.size(); ++k) {
            up[c].push_back(columns_[c].up[size_t(e[k])]);
            down[c].push_back(columns_[c].down[size_t(e[k])]);
        }
    }
    std::map<std::tuple<int, int, int>, double> across;  // rays from (column, node) to a column
    for (const Lateral& l : lateral_) {
        const double x = lo_ + (l.bin + 0.5) * (hi_ - lo_) / bins_;
        const int from = ownerOf(planes[size_t(l.from)], x), to = ownerOf(planes[size_t(l.to)], x);
        across[{l.from, from, l.to}] += l.rays;
        const int s = to > from ? 1 : -1;
        for (int j = from; j != to; j += s) {  // passed on along the axis, from the node of the sender's index
            busy[size_t(l.to)][size_t(j)] += l.rays * 2 * columns_[size_t(l.to)].perCrossing;
            (s > 0 ? up : down)[size_t(l.to)][size_t(s > 0 ? j : j - 1)] += l.rays;
            f.passes += l.rays;
        }
    }
    double rays = 0;
    for (size_t c = 0; c < columns_.size(); ++c) {
        for (size_t j = 0; j < busy[c].size(); ++j) {
            const double start = startNs && c < startNs->size() && j < (*startNs)[c].size() ? (*startNs)[c][j] : 0.0;
            f.nodeNs = std::max(f.nodeNs, start + busy[c][j]);
        }
        for (double x : up[c]) rays = std::max(rays, x);
        for (double x : down[c]) rays = std::max(rays, x);
    }
    for (const auto& [key, x] : across) rays = std::max(rays, x);
    f.linkNs = rays * wirePerRay_;
    f.frameNs = std::max({f.nodeNs, f.linkNs, kTandem * std::min(f.nodeNs, f.linkNs)});
    return f;
}

std::vector<int> FrameForecast::gridEdges() const {
    const double cols = double(columns_.size());
    const int m = std::clamp(int(std::sqrt(2 * kSearchBudget / (cols * (n_ + 1)))), std::min(bins_, 4 * n_),
                             std::min(bins_, kMaxGrid));
    std::vector<int> e;
    for (int i = 0; i <= m; ++i) e.push_back(int(std::lround(double(i) * bins_ / m)));
    return e;
}

int FrameForecast::minCells(int cells) const {
    return std::max(1, int(std::ceil(minBins_ * cells / bins_ - 1e-9)) + 1);
}

std::vector<double> FrameForecast::planesOf(const std::vector<int>& edges) const {
    // Inner edges as positions, every box at least the minimum thickness.
    const double minT = planeSpacing(minBins_ * (hi_ - lo_) / bins_);
    std::vector<double> x(size_t(n_ + 1));
    x.front() = lo_;
    x.back() = hi_;
    for (int k = 1; k < n_; ++k) x[size_t(k)] = lo_ + (hi_ - lo_) * edges[size_t(k)] / bins_;
    for (int k = 1; k < n_; ++k) x[size_t(k)] = std::max(x[size_t(k)], x[size_t(k - 1)] + minT);
    for (int k = n_ - 1; k >= 1; --k) x[size_t(k)] = std::min(x[size_t(k)], x[size_t(k + 1)] - minT);
    return std::vector<double>(x.begin() + 1, x.end() - 1);
}

namespace {
PartCosts costsOn(const std::vector<int>& grid) { return PartCosts{int(grid.size()) - 1, std::vector<double>(grid.size() * grid.size(), 0.0)}; }
}  // namespace

std::vector<double> FrameForecast::searchOn(const std::vector<int>& grid, const PartCosts& pc) const {
    std::vector<int> e = minimaxSplit(pc, n_, minCells(pc.m));
    for (int& x : e) x = grid[size_t(x)];
    return planesOf(e);
}

FrameForecast::Splits FrameForecast::splits() const {
    const std::vector<int> grid = gridEdges();
    const int m = int(grid.size()) - 1;
    Splits out;
    PartCosts pc = costsOn(grid), all = costsOn(grid);  // a column's; the dearest column's
    for (const Column& c : columns_) {
        for (int j = 1; j <= m; ++j)
            for (int i = 0; i < j; ++i) {
                const double x = partCost(c, grid[size_t(i)], grid[size_t(j)]);
                pc.at(i, j) = x;
                all.at(i, j) = std::max(all.at(i, j), x);
            }
        out.perColumn.push_back(searchOn(grid, pc));
    }
    out.aligned = InnerPlanes(columns_.size(), searchOn(grid, all));
    return out;
}

}  // namespace rt
