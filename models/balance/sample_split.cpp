#include "balance/sample_split.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "balance/move_forecast.h"
#include "balance/plane_spacing.h"

namespace rt {

bool inSample(uint32_t pixel, uint32_t width) {
    return (pixel % width) % kSampleSide == 0 && (pixel / width) % kSampleSide == 0;
}

void ColumnSample::add(double lo, double hi, const std::vector<double>& bins, const std::vector<double>& sideBins,
                       double passPs, const std::vector<double>& crossBins) {
    if (edges.empty()) edges.push_back(lo);
    else faces.push_back(lo);
    moves.push_back(passPs);
    if (!sides) boxes.push_back(1);
    const double w = (hi - lo) / double(bins.size());
    double box = 0;
    for (size_t k = 0; k < bins.size(); ++k) {
        edges.push_back(k + 1 == bins.size() ? hi : lo + double(k + 1) * w);
        mass.push_back(bins[k]);
        side.push_back(k < sideBins.size() ? sideBins[k] : 0.0);
        if (crossings) cross.push_back((k < crossBins.size() ? crossBins[k] : 0.0) + (k == 0 ? crossOver : 0.0));
        box += bins[k];
    }
    if (crossings) crossOver = crossBins.size() > bins.size() ? crossBins[bins.size()] : 0.0;
    busiestBox = std::max(busiestBox, box);
}

void ColumnSample::compress(int cells) {
    if (int(mass.size()) <= cells) return;
    const double all = total();
    const double allSide = std::accumulate(side.begin(), side.end(), 0.0);
    const double allCross = std::accumulate(cross.begin(), cross.end(), 0.0);
    std::vector<double> e{lo()}, m, s, x2;
    if (all > 0) {
        double done = 0;  // the work below edge e.back()
        for (int j = 1; j < cells; ++j) {
            const double x = cut(e.back(), hi(), all * j / cells - done);
            if (!(x > e.back()) || !(x < hi())) continue;
            m.push_back(within(e.back(), x));
            s.push_back(sideWithin(e.back(), x));
            if (crossings) x2.push_back(below(edges, cross, x) - below(edges, cross, e.back()));
            done += m.back();
            e.push_back(x);
        }
    }
    m.push_back(all - std::accumulate(m.begin(), m.end(), 0.0));
    s.push_back(std::max(0.0, allSide - std::accumulate(s.begin(), s.end(), 0.0)));
    if (crossings) x2.push_back(allCross - std::accumulate(x2.begin(), x2.end(), 0.0));
    e.push_back(hi());
    edges = std::move(e);
    mass = std::move(m);
    side = std::move(s);
    if (crossings) cross = std::move(x2);
}

void ColumnSample::groupBoxes(int most) {
    while (int(moves.size()) > std::max(1, most)) {
        size_t j = 0;  // the neighbouring pair of fewest boxes (the lowest of equals) is merged
        for (size_t k = 1; k + 1 < moves.size(); ++k)
            if (boxes[k] + boxes[k + 1] < boxes[j] + boxes[j + 1]) j = k;
        moves[j] += moves[j + 1];
        boxes[j] += boxes[j + 1];
        moves.erase(moves.begin() + long(j) + 1);
        boxes.erase(boxes.begin() + long(j) + 1);
        faces.erase(faces.begin() + long(j));
    }
}

std::vector<BoxPass> ColumnSample::passes() const {
    std::vector<BoxPass> p;
    double from = lo();
    for (size_t i = 0; i < moves.size() && i <= faces.size(); ++i) {
        const double to = i < faces.size() ? faces[i] : hi();
        p.push_back({from, to, moves[i], boxes.empty() ? 1.0 : boxes[i]});
        from = to;
    }
    return p;
}

double ColumnSample::faceAt(int i) const { return moves.empty() ? hi() : faceAmong(passes(), i); }

double faceAmong(const std::vector<BoxPass>& passes, int i) {
    double below = 0;  // boxes below the entry
    for (const BoxPass& e : passes) {
        if (double(i) + 1 < below + e.boxes) return e.lo + (e.hi - e.lo) * (double(i) + 1 - below) / e.boxes;
        below += e.boxes;
    }
    return passes.empty() ? 0.0 : passes.back().hi;
}

bool sidesFit(int columnLength) {
    return (kSampleValues - 5 - (columnLength - 1)) / 3 >= kSampleMinCells;
}

int ColumnSample::cellsWithin(int values) const {
    // (4 values ahead, the faces, one edge more than the cells, and per
    // cell an edge and a mass, and with the sides a side; with the sides,
    // the boxes' passes, one a box, come on top; without, the passes and
    // the boxes of each group, at most kSampleGroups of them, take their
    // room too)
    const int ahead = 5 + int(faces.size()) + (sides ? 0 : int(moves.size() + boxes.size())) + (crossings ? 1 : 0);
    return std::max(1, (values - ahead) / ((sides ? 3 : 2) + (crossings ? 1 : 0)));
}

std::vector<double> ColumnSample::values() const {
    // Beside no column (a mesh one box across), no sides: a message no
    // longer than it must be (on a long column a longer sum holds every ray
    // behind it to its pace).
    std::vector<double> v{busiestBox, startedAt, (sides ? 1.0 : 0.0) + (crossings ? 2.0 : 0.0), double(faces.size())};
    for (const std::vector<double>* part : {&faces, &moves, &boxes, &edges, &mass, &side, &cross})
        if (sides ? part != &boxes : part != &side) v.insert(v.end(), part->begin(), part->end());
    if (crossings) v.push_back(crossOver);
    return v;
}

ColumnSample ColumnSample::of(const std::vector<double>& v) {
    ColumnSample c;
    if (v.size() < 4 || !(v[2] == 0 || v[2] == 1 || v[2] == 2 || v[2] == 3) || !(v[3] >= 0) ||
        !(v[3] <= double(v.size())) || v[3] != std::floor(v[3]))
        return c;
    const bool sides = v[2] == 1 || v[2] == 3, crossings = v[2] >= 2;
    const size_t f = size_t(v[3]), per = (sides ? 3 : 2) + (crossings ? 1 : 0);  // (values per cell)
    const size_t b = sides ? 0 : f + 1;  // (the boxes a group, without sides)
    const size_t ahead = 4 + f + (f + 1) + b + 1 + (crossings ? 1 : 0);  // (the faces, the passes, the boxes, the first edge)
    if (v.size() < ahead + per || (v.size() - ahead) % per != 0) return c;
    const size_t k = (v.size() - ahead) / per;
    c.busiestBox = v[0];
    c.startedAt = v[1];
    auto at = v.begin() + 4;
    for (auto [part, n] : {std::pair{&c.faces, f}, {&c.moves, f + 1}, {&c.boxes, b}, {&c.edges, k + 1}, {&c.mass, k},
                           {&c.side, sides ? k : 0}, {&c.cross, crossings ? k : 0}}) {
        part->assign(at, at + long(n));
        at += long(n);
    }
    if (!sides) c.side.assign(k, 0.0);
    c.sides = sides;
    c.crossings = crossings;
    if (crossings) c.crossOver = *at;
    return c;
}

bool ColumnSample::wellFormed() const {
    if (mass.empty() || edges.size() != mass.size() + 1 || side.size() != mass.size()) return false;
    if (crossings != (cross.size() == mass.size())) return false;
    if (moves.size() != faces.size() + 1 || boxes.size() != (sides ? 0 : moves.size())) return false;
    for (double m : moves)
        if (!(m >= 0)) return false;
    for (double n : boxes)
        if (!(n >= 1) || n != std::floor(n)) return false;
    for (size_t k = 0; k < mass.size(); ++k)
        if (!(edges[k] < edges[k + 1]) || !(mass[k] >= 0) || !(side[k] >= 0)) return false;
    for (size_t k = 0; k < faces.size(); ++k)
        if (!(faces[k] > lo() && faces[k] < hi()) || (k > 0 && !(faces[k] > faces[k - 1]))) return false;
    return busiestBox >= 0 && startedAt >= 0;
}

double ColumnSample::crossingsAt(double x) const { return crossings ? std::max(0.0, below(edges, cross, x)) : 0.0; }

double ColumnSample::total() const { return std::accumulate(mass.begin(), mass.end(), 0.0); }

double ColumnSample::below(const std::vector<double>& e, const std::vector<double>& m, double x) {
    double sum = 0;
    for (size_t k = 0; k < m.size(); ++k) {
        if (x <= e[k]) return sum;
        sum += m[k] * std::min(1.0, (x - e[k]) / (e[k + 1] - e[k]));
    }
    return sum;
}

double ColumnSample::within(double a, double b) const {
    return b > a ? below(edges, mass, b) - below(edges, mass, a) : 0.0;
}

double ColumnSample::sideWithin(double a, double b) const {
    return b > a ? below(edges, side, b) - below(edges, side, a) : 0.0;
}

double ColumnSample::cut(double from, double limit, double work) const {
    double left = work;
    for (size_t k = 0; k < mass.size(); ++k) {
        const double a = std::max(from, edges[k]), z = std::min(limit, edges[k + 1]);
        if (!(z > a)) continue;
        const double part = mass[k] * (z - a) / (edges[k + 1] - edges[k]);
        if (part > 0 && part >= left) return a + (z - a) * (left / part);
        left -= part;
    }
    return limit;
}

namespace {

// Planes from the bottom up, each part holding at most `most` of the work
// (each at least minThickness, leaving room for the parts above); whether
// the last part then holds at most `most` too.
bool fillTo(const ColumnSample& p, int count, double minThickness, double most, std::vector<double>& planes) {
    planes.clear();
    double x = p.lo();
    for (int k = 1; k < count; ++k) {
        const double top = p.hi() - double(count - k) * minThickness;
        double c = p.cut(x, p.hi(), most);
        c = std::clamp(c, x + minThickness, top);
        if (p.within(x, c) > most * (1 + 1e-12)) return false;  // the thinnest part allowed is already dearer
        planes.push_back(c);
        x = c;
    }
    return p.within(x, p.hi()) <= most * (1 + 1e-12);
}

}  // namespace

std::vector<double> splitBySample(const ColumnSample& column, int count, double minThickness) {
    minThickness = planeSpacing(minThickness);
    const double total = column.total();
    if (!(total > 0) || count < 2) return {};
    // The least `most` that fits, by bisection between an even share and all of it.
    double lo = total / count, hi = total;
    std::vector<double> planes;
    if (!fillTo(column, count, minThickness, hi, planes)) return {};
    for (int i = 0; i < 60 && hi - lo > 1e-9 * total; ++i) {
        const double mid = 0.5 * (lo + hi);
        (fillTo(column, count, minThickness, mid, planes) ? hi : lo) = mid;
    }
    fillTo(column, count, minThickness, hi, planes);
    // The slack evenly: each part an even share of what is left above it,
    // where that keeps every part within the least `most` (filling each to
    // it would leave the last parts empty).
    std::vector<double> even;
    double x = column.lo();
    for (int k = 1; k < count; ++k) {
        const double top = column.hi() - double(count - k) * minThickness;
        const double share = std::min(hi, column.within(x, column.hi()) / double(count - k + 1));
        const double c = std::clamp(column.cut(x, column.hi(), share), x + minThickness, top);
        even.push_back(c);
        x = c;
    }
    return dearestPart(column, even) <= hi * (1 + 1e-9) ? even : planes;
}

namespace {
// The work of each part between `planes`.
std::vector<double> partsOf(const ColumnSample& column, const std::vector<double>& planes) {
    std::vector<double> parts;
    double from = column.lo();
    for (size_t i = 0; i <= planes.size(); ++i) {
        const double to = i < planes.size() ? planes[i] : column.hi();
        parts.push_back(column.within(from, to));
        from = to;
    }
    return parts;
}
// The dearest of `parts`; with the crossings (--sample-links on), each at
// least as dear as its link up: the sample's rays across its upper plane,
// each a ray's time on the wire. (The link is a resource of its own: its
// time bounds the part's, it does not add to the node's work and passes.)
double dearestOf(const ColumnSample& column, const std::vector<double>& planes, std::vector<double> parts) {
    if (column.crossings)
        for (size_t i = 0; i < planes.size(); ++i) parts[i] = std::max(parts[i], column.wirePs * column.crossingsAt(planes[i]));
    return *std::max_element(parts.begin(), parts.end());
}
}  // namespace

double dearestPart(const ColumnSample& column, const std::vector<double>& planes) {
    return dearestOf(column, planes, partsOf(column, planes));
}

double dearestPartWithPasses(const ColumnSample& column, const std::vector<double>& planes,
                             const std::vector<std::vector<double>>& beside) {
    if (!column.sides || beside.empty()) return dearestPart(column, planes);
    std::vector<double> parts = partsOf(column, planes);
    const auto partOf = [](const std::vector<double>& faces, double x) {
        return size_t(std::upper_bound(faces.begin(), faces.end(), x) - faces.begin());
    };
    const double share = 1.0 / double(beside.size());
    for (const std::vector<double>& there : beside) {
        const bool known = there.size() == planes.size();
        // Between consecutive planes and faces beside, a crossing's own
        // part i and the part j of the node of its index beside are the
        // same throughout: it is passed from j to i, through every node
        // between (unknown faces beside: once, in its own part).
        std::vector<double> cuts = planes;
        if (known) cuts.insert(cuts.end(), there.begin(), there.end());
        cuts.push_back(column.hi());
        std::sort(cuts.begin(), cuts.end());
        double a = column.lo();
        for (double b : cuts) {
            b = std::min(b, column.hi());
            if (!(b > a)) continue;
            const double passes = share * column.sideWithin(a, b), mid = 0.5 * (a + b);
            const size_t i = partOf(planes, mid), j = known ? partOf(there, mid) : i;
            if (!known) parts[i] += passes;
            else if (i != j)
                for (size_t k = std::min(i, j); k <= std::max(i, j); ++k)
                    parts[k] += (k == i || k == j ? 0.5 : 1.0) * passes;
            a = b;
        }
    }
    return dearestOf(column, planes, parts);
}

double holdingPart(const ColumnSample& column, const std::vector<std::vector<double>>& beside) {
    // (with the crossings, the faces as they stand may leave a box's link dearer than its work)
    if (!column.crossings && (!column.sides || beside.empty())) return column.busiestBox;
    return std::max(column.busiestBox, dearestPartWithPasses(column, column.faces, beside));
}

double sampleMovePs(const ColumnSample& column, const std::vector<double>& planes, double hopPs) {
    const std::vector<BoxPass> boxes = column.passes();
    double longest = 0;
    for (size_t i = 0; i < planes.size(); ++i)
        longest = std::max(longest, chainPs(boxes, faceAmong(boxes, int(i)), planes[i], hopPs));
    return longest;
}

bool samplePays(const ColumnSample& column, double hold, double dearest, double elapsed, double movePs) {
    const double share = double(kSampleSide * kSampleSide);  // the frame's work over the sample's
    hold *= share;
    if (!(hold > 0)) return false;
    const double inPlace = elapsed + std::max(0.0, elapsed - column.startedAt);  // (the planes come down as the sum went up)
    const double left = std::max(0.0, 1 - inPlace / hold);
    return left * (hold - share * dearest) - movePs > kSampleMinGain * hold;
}

}  // namespace rt
