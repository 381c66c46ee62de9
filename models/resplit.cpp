#include "resplit.h"

#include <algorithm>
#include <stdexcept>

namespace rt {

std::vector<double> resplitPlanes(const std::vector<double>& edges, const std::vector<double>& busy, double minThickness) {
    const size_t n = busy.size();
    if (n == 0 || edges.size() != n + 1) throw std::invalid_argument("resplit: N + 1 planes and N busy times");
    double total = 0;
    for (double b : busy) total += std::max(0.0, b);
    std::vector<double> out(edges);
    if (total > 0) {
        // Plane k where the busy time below it, spread evenly over each box,
        // reaches k / N of the column's.
        size_t box = 0;
        double below = 0;  // busy time of the boxes before `box`
        for (size_t k = 1; k < n; ++k) {
            const double target = total * double(k) / double(n);
            while (box < n && below + std::max(0.0, busy[box]) < target) below += std::max(0.0, busy[box++]);
            if (box == n) {
                out[k] = edges[n];
                continue;
            }
            const double share = busy[box] > 0 ? (target - below) / busy[box] : 0.0;
            out[k] = edges[box] + share * (edges[box + 1] - edges[box]);
        }
    }
    // Every box at least the minimum thick: push up from the bottom, then down from the top.
    for (size_t k = 1; k < n; ++k) out[k] = std::max(out[k], out[k - 1] + minThickness);
    for (size_t k = n - 1; k >= 1; --k) out[k] = std::min(out[k], out[k + 1] - minThickness);
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
