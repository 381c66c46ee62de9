#include "pixel_sum.h"

#include <algorithm>
#include <climits>
#include <cmath>

namespace rt {

namespace {
constexpr double kScale = kFixedRange;             // 2^kFixedBits: scaling by it is exact
constexpr double kUnit = 1.0 / kFixedRange;        // 2^-kFixedBits

// s (a component scaled by 2^40, so |s| < 2^80) rounded to the nearest
// integer, halves away from zero, whatever the floating-point rounding mode.
__int128 roundToUnits(double s) {
    if (std::fabs(s) < 0x1p62) {  // nearly always: in 64 bits, without a library call
        int64_t i = int64_t(s);          // towards zero, exact
        const double frac = s - double(i);  // exact (Sterbenz, or s itself when |s| < 1)
        if (frac >= 0.5) ++i;
        else if (frac <= -0.5) --i;
        return i;
    }
    return __int128(std::round(s));  // an integer already (|s| >= 2^53): converts exactly
}
}  // namespace

bool toFixed(const Vec3& rgb, FixedRgb& out) {
    for (int a = 0; a < 3; ++a)
        if (!(std::fabs(rgb[a]) < kFixedRange)) return false;  // (also NaN)
    for (int a = 0; a < 3; ++a) out.c[a] = roundToUnits(rgb[a] * kScale);
    return true;
}

Vec3 toDouble(const FixedRgb& sum) {
    return Vec3(double(sum.c[0]) * kUnit, double(sum.c[1]) * kUnit, double(sum.c[2]) * kUnit);
}

void PixelSums::add(size_t i, const Contribution& c) {
    FixedRgb v;
    if (!toFixed(c.rgb, v)) {
        aside_.emplace_back(i, c);
        sorted_ = false;
        return;
    }
    for (int a = 0; a < 3; ++a) {
        // (the builtin stores the wrapped sum on overflow: hence the temporary)
        int64_t& narrow = narrow_[i].c[a];
        int64_t sum;
        const bool fits = v.c[a] >= INT64_MIN && v.c[a] <= INT64_MAX;
        if (fits && !__builtin_add_overflow(narrow, int64_t(v.c[a]), &sum)) narrow = sum;
        else wide_[i].c[a] += v.c[a];
    }
}

Vec3 PixelSums::value(size_t i) {
    FixedRgb sum;
    for (int a = 0; a < 3; ++a) sum.c[a] = narrow_[i].c[a];
    if (!wide_.empty()) {
        const auto w = wide_.find(i);
        if (w != wide_.end())
            for (int a = 0; a < 3; ++a) sum.c[a] += w->second.c[a];
    }
    const Vec3 fixed = toDouble(sum);
    if (aside_.empty()) return fixed;
    if (!sorted_) {
        std::sort(aside_.begin(), aside_.end(), [](const auto& a, const auto& b) {
            return a.first != b.first ? a.first < b.first : a.second.key < b.second.key;
        });
        sorted_ = true;
    }
    auto it = std::partition_point(aside_.begin(), aside_.end(), [&](const auto& x) { return x.first < i; });
    Vec3 rest(0.0);
    for (; it != aside_.end() && it->first == i; ++it) rest += it->second.rgb;
    return fixed + rest;
}

void PixelSums::clear() {
    std::fill(narrow_.begin(), narrow_.end(), Narrow{});
    wide_.clear();
    aside_.clear();
    sorted_ = true;
}

}  // namespace rt
