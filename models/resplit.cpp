#include "resplit.h"

#include <algorithm>
#include <stdexcept>

namespace rt {

std::vector<double> resplitPlanes(const std::vector<double>& edges, const std::vector<double>& busy, double minThickness) {
    const size_t n = busy.size();
    if (n == 0 || edges.size() != n + 1) throw std::invalid_argument("resplit: N + 1 planes and N busy times");
    // Each box's busy time, spread evenly over it: one piece per box.
    std::vector<WorkPiece> pieces;
    for (size_t k = 0; k < n; ++k) pieces.push_back({edges[k], edges[k + 1], busy[k]});
    return resplitPlanes(pieces, edges.front(), edges.back(), int(n), minThickness,
                         std::vector<double>(edges.begin() + 1, edges.end() - 1));
}

std::vector<double> resplitPlanes(const std::vector<WorkPiece>& pieces, double lo, double hi, int count,
                                  double minThickness, const std::vector<double>& fallback) {
    if (count < 1 || fallback.size() != size_t(count - 1) || !(hi > lo)) throw std::invalid_argument("resplit: a column of the wrong size");
    // The work below x is piecewise linear between the pieces' ends (a
    // piece of no width is a step): sweep them in order, then interpolate
    // each target within its stretch.
    struct Change {
        double x, density, step;  // from x on: density changes by `density`; the work below jumps by `step`
        bool operator<(const Change& o) const { return x < o.x; }
    };
    std::vector<Change> changes;
    double total = 0;
    for (const WorkPiece& p : pieces) {
        if (!(p.work > 0)) continue;
        const double a = std::clamp(p.from, lo, hi), b = std::clamp(p.to, lo, hi);
        total += p.work;
        if (b > a) {
            changes.push_back({a, p.work / (b - a), 0});
            changes.push_back({b, -p.work / (b - a), 0});
        } else {
            changes.push_back({a, 0, p.work});
        }
    }
    std::vector<double> out(size_t(count + 1));
    out.front() = lo;
    out.back() = hi;
    if (!(total > 0)) {
        std::copy(fallback.begin(), fallback.end(), out.begin() + 1);
    } else {
        std::sort(changes.begin(), changes.end());
        int k = 1;
        double x = lo, cum = 0, density = 0;
        for (size_t i = 0; i <= changes.size() && k < count; ++i) {
            const double next = i < changes.size() ? changes[i].x : hi;
            const double reach = cum + density * (next - x);  // the work below `next`, before its changes
            for (; k < count && total * double(k) / double(count) <= reach; ++k) {
                const double target = total * double(k) / double(count);
                out[size_t(k)] = density > 0 ? x + (target - cum) / density : x;
            }
            x = next;
            cum = reach;
            if (i < changes.size()) {
                density += changes[i].density;
                cum += changes[i].step;
                for (; k < count && total * double(k) / double(count) <= cum; ++k) out[size_t(k)] = x;
            }
        }
        for (; k < count; ++k) out[size_t(k)] = hi;
    }
    for (int k = 1; k < count; ++k) out[size_t(k)] = std::max(out[size_t(k)], out[size_t(k - 1)] + minThickness);
    for (int k = count - 1; k >= 1; --k) out[size_t(k)] = std::min(out[size_t(k)], out[size_t(k + 1)] - minThickness);
    return std::vector<double>(out.begin() + 1, out.end() - 1);
}

double timeAveraged(const std::vector<std::pair<double, double>>& history, double end) {
    if (history.empty()) throw std::invalid_argument("resplit: an empty boundary history");
    if (!(end > 0)) return history.back().second;
    double sum = 0;
    for (size_t i = 0; i < history.size(); ++i) {
        const double from = i == 0 ? 0.0 : std::min(history[i].first, end);  // the first position holds from 0
        const double to = i + 1 < history.size() ? std::min(history[i + 1].first, end) : end;
        sum += history[i].second * std::max(0.0, to - from);
    }
    return sum / end;
}

}  // namespace rt
