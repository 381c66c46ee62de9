#include "analysis/stability.h"

#include <cmath>

namespace rt {

const char* stabilityName(Stability s) {
    switch (s) {
        case Stability::Converged: return "converged";
        case Stability::Oscillating: return "oscillating";
        case Stability::Diverging: return "diverging";
    }
    return "?";
}

StabilityVerdict judgeStability(const std::vector<BoundaryHistory>& boundaries, Picos renderTime,
                                double initialThickness) {
    StabilityVerdict v;
    const Picos half = renderTime / 2, threeQuarters = renderTime / 4 * 3;
    for (const BoundaryHistory& h : boundaries) {
        // Moves (steps) made after the transient, with their times.
        std::vector<std::pair<Picos, double>> steps;
        for (size_t i = 1; i < h.positions.size(); ++i)
            if (h.positions[i].first >= half)
                steps.push_back({h.positions[i].first, h.positions[i].second - h.positions[i - 1].second});
        int reversals = 0;
        double sum = 0, q3 = 0, q4 = 0;
        int n3 = 0, n4 = 0;
        for (size_t i = 0; i < steps.size(); ++i) {
            const double d = std::abs(steps[i].second);
            sum += d;
            if (steps[i].first < threeQuarters) {
                q3 += d;
                ++n3;
            } else {
                q4 += d;
                ++n4;
            }
            if (i > 0 && (steps[i].second > 0) != (steps[i - 1].second > 0)) ++reversals;
        }
        Stability s = Stability::Converged;
        const double mean = steps.empty() ? 0.0 : sum / double(steps.size());
        if (reversals >= 3 && mean > 0.05 * initialThickness) {
            s = Stability::Oscillating;
            const double m3 = n3 ? q3 / n3 : 0.0, m4 = n4 ? q4 / n4 : 0.0;
            if (n3 && n4 && m4 >= 1.5 * m3) s = Stability::Diverging;
        }
        (s == Stability::Converged ? v.converged : s == Stability::Oscillating ? v.oscillating : v.diverging)++;
        if (int(s) > int(v.overall)) v.overall = s;
    }
    return v;
}

}  // namespace rt
