#include "balance/sample_split.h"

#include <algorithm>
#include <numeric>

namespace rt {

bool inSample(uint32_t pixel, uint32_t width) {
    return (pixel % width) % kSampleSide == 0 && (pixel / width) % kSampleSide == 0;
}

void ColumnSample::add(double lo, double hi, const std::vector<double>& bins) {
    if (edges.empty()) edges.push_back(lo);
    const double w = (hi - lo) / double(bins.size());
    double box = 0;
    for (size_t k = 0; k < bins.size(); ++k) {
        edges.push_back(k + 1 == bins.size() ? hi : lo + double(k + 1) * w);
        mass.push_back(bins[k]);
        box += bins[k];
    }
    busiestBox = std::max(busiestBox, box);
}

void ColumnSample::compress(int cells) {
    if (int(mass.size()) <= cells) return;
    const double all = total();
    std::vector<double> e{lo()}, m;
    if (all > 0) {
        double done = 0;  // the work below edge e.back()
        for (int j = 1; j < cells; ++j) {
            const double x = cut(e.back(), hi(), all * j / cells - done);
            if (!(x > e.back()) || !(x < hi())) continue;
            m.push_back(within(e.back(), x));
            done += m.back();
            e.push_back(x);
        }
    }
    m.push_back(all - std::accumulate(m.begin(), m.end(), 0.0));
    e.push_back(hi());
    edges = std::move(e);
    mass = std::move(m);
}

std::vector<double> ColumnSample::values() const {
    std::vector<double> v{busiestBox, startedAt};
    v.insert(v.end(), edges.begin(), edges.end());
    v.insert(v.end(), mass.begin(), mass.end());
    return v;
}

ColumnSample ColumnSample::of(const std::vector<double>& v) {
    ColumnSample c;
    if (v.size() < 5 || v.size() % 2 == 0) return c;
    const size_t k = (v.size() - 3) / 2;
    c.busiestBox = v[0];
    c.startedAt = v[1];
    c.edges.assign(v.begin() + 2, v.begin() + 3 + long(k));
    c.mass.assign(v.begin() + 3 + long(k), v.end());
    return c;
}

bool ColumnSample::wellFormed() const {
    if (mass.empty() || edges.size() != mass.size() + 1) return false;
    for (size_t k = 0; k < mass.size(); ++k)
        if (!(edges[k] < edges[k + 1]) || !(mass[k] >= 0)) return false;
    return busiestBox >= 0 && startedAt >= 0;
}

double ColumnSample::total() const { return std::accumulate(mass.begin(), mass.end(), 0.0); }

double ColumnSample::below(double x) const {
    double sum = 0;
    for (size_t k = 0; k < mass.size(); ++k) {
        if (x <= edges[k]) return sum;
        sum += mass[k] * std::min(1.0, (x - edges[k]) / (edges[k + 1] - edges[k]));
    }
    return sum;
}

double ColumnSample::within(double a, double b) const { return b > a ? below(b) - below(a) : 0.0; }

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

double dearestPart(const ColumnSample& column, const std::vector<double>& planes) {
    double most = 0, from = column.lo();
    for (double x : planes) {
        most = std::max(most, column.within(from, x));
        from = x;
    }
    return std::max(most, column.within(from, column.hi()));
}

bool samplePays(const ColumnSample& column, double dearest, double elapsed) {
    const double share = double(kSampleSide * kSampleSide);  // the frame's work over the sample's
    const double hold = share * column.busiestBox;
    if (!(hold > 0)) return false;
    const double inPlace = elapsed + std::max(0.0, elapsed - column.startedAt);  // (the planes come down as the sum went up)
    const double left = std::max(0.0, 1 - inPlace / hold);
    return left * (hold - share * dearest) > kSampleMinGain * hold;
}

}  // namespace rt
