#include "balance/policy.h"

#include <algorithm>
#include <cmath>

namespace rt {

void WorkProfile::add(double where, double work) {
    if (bins.empty() || !std::isfinite(where)) return;
    const int n = int(bins.size());
    const int k = std::clamp(int(std::floor((where - lo) / binWidth())), 0, n - 1);
    bins[size_t(k)] += work;
}

double WorkProfile::within(double a, double b) const {
    if (bins.empty() || !(b > a)) return 0;
    const double w = binWidth();
    double sum = 0;
    for (size_t k = 0; k < bins.size(); ++k) {
        const double x0 = lo + double(k) * w, x1 = x0 + w;
        const double overlap = std::min(b, x1) - std::max(a, x0);
        if (overlap > 0) sum += bins[k] * overlap / w;
    }
    return sum;
}

double WorkProfile::cut(double from, double limit, double work, double even) const {
    const bool up = limit > from;
    if (!(within(std::min(from, limit), std::max(from, limit)) > 0)) {  // nothing recorded: spread evenly
        if (!(even > 0)) return limit;
        const double c = from + (up ? 1 : -1) * work / even;
        return up ? std::min(c, limit) : std::max(c, limit);
    }
    const int n = int(bins.size());
    const double w = binWidth();
    double x = from, left = work;
    int k = up ? int(std::floor((x - lo) / w)) : int(std::ceil((x - lo) / w)) - 1;
    k = std::clamp(k, 0, n - 1);
    while (k >= 0 && k < n) {
        const double edge = up ? std::min(lo + double(k + 1) * w, limit) : std::max(lo + double(k) * w, limit);
        const double piece = std::max(0.0, up ? edge - x : x - edge);
        const double mass = bins[size_t(k)] * piece / w;
        if (mass > 0 && mass >= left) return x + (up ? 1 : -1) * piece * (left / mass);
        left -= mass;
        x = edge;
        if (x == limit) break;
        k += up ? 1 : -1;
    }
    return limit;
}

std::optional<double> clampGive(const SlideQuery& q, double delta) {
    const double lo = q.own.lo[q.axis], hi = q.own.hi[q.axis];
    const double thickness = hi - lo;
    const double room = thickness - q.minThickness;  // the most it may give
    if (!(room > 0) || !(delta > 0)) return std::nullopt;
    delta = std::min(delta, room);
    if (!(delta > 1e-9 * thickness)) return std::nullopt;
    return q.upper ? hi - delta : lo + delta;
}

}  // namespace rt
