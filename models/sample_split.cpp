#include "sample_split.h"

#include <algorithm>

namespace rt {

bool inSample(uint32_t pixel, uint32_t width) {
    return (pixel % width) % kSampleSide == 0 && (pixel / width) % kSampleSide == 0;
}

void ColumnSample::add(double lo, double hi, const std::vector<double>& bins) {
    values.push_back(lo);
    values.push_back(hi);
    values.insert(values.end(), bins.begin(), bins.end());
}

bool ColumnSample::wellFormed() const {
    const size_t stride = kSampleBins + 2;
    if (values.empty() || values.size() % stride) return false;
    for (size_t n = 0; n < values.size(); n += stride) {
        if (!(values[n] < values[n + 1])) return false;
        if (n && values[n] != values[n - stride + 1]) return false;
        for (size_t k = 0; k < size_t(kSampleBins); ++k)
            if (!(values[n + 2 + k] >= 0)) return false;
    }
    return true;
}

double ColumnSample::total() const {
    double t = 0;
    for (size_t n = 0; n < values.size(); n += kSampleBins + 2)
        for (size_t k = 0; k < size_t(kSampleBins); ++k) t += values[n + 2 + k];
    return t;
}

double ColumnSample::below(double x) const {
    double sum = 0;
    for (size_t n = 0; n < values.size(); n += kSampleBins + 2) {
        const double lo = values[n], hi = values[n + 1], w = (hi - lo) / kSampleBins;
        for (size_t k = 0; k < size_t(kSampleBins); ++k) {
            const double a = lo + double(k) * w;
            if (x <= a) return sum;
            sum += values[n + 2 + k] * std::min(1.0, (x - a) / w);
        }
    }
    return sum;
}

double ColumnSample::within(double a, double b) const { return b > a ? below(b) - below(a) : 0.0; }

double ColumnSample::cut(double from, double limit, double work) const {
    double left = work;
    for (size_t n = 0; n < values.size(); n += kSampleBins + 2) {
        const double lo = values[n], hi = values[n + 1], w = (hi - lo) / kSampleBins;
        for (size_t k = 0; k < size_t(kSampleBins); ++k) {
            const double a = std::max(from, lo + double(k) * w), z = std::min(limit, lo + double(k + 1) * w);
            if (!(z > a)) continue;
            const double mass = values[n + 2 + k] * (z - a) / w;
            if (mass > 0 && mass >= left) return a + (z - a) * (left / mass);
            left -= mass;
        }
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
    double from = column.lo();
    for (double c : even) {
        if (column.within(from, c) > hi * (1 + 1e-9)) return planes;
        from = c;
    }
    return column.within(from, column.hi()) <= hi * (1 + 1e-9) ? even : planes;
}

}  // namespace rt
