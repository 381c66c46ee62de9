// The sum of a pixel's contributions, the same whatever order they come in.
//
// Each colour component of a contribution is rounded once to a multiple of
// 2^-40 (kFixedBits) and added as an integer: integer addition is exact, so
// the order of the additions cannot change a bit of the sum. Every renderer
// (rtref, and the frame buffer's units in rtsim) sums this way, so a pixel
// does not depend on where or when its contributions were traced.
//
// A pixel's sum is kept in 64 bits per component (24 bytes a pixel), enough
// for sums below 2^23 in magnitude, which is every sane scene's; what would
// overflow them (a huge contribution, or many) is added instead to a 128-bit
// sum for that pixel, kept apart (wide_), and the pixel is the exact integer
// sum of both: which part a contribution went to cannot change it. A 128-bit
// sum cannot overflow before 2^47 contributions of the largest size taken
// (magnitude below 2^40, kFixedRange; a colour of 10^12 is far outside any
// sane scene). A contribution outside that range (or not finite) is kept
// aside and summed in path-key order, as every contribution once was, and
// added to the fixed-point part at the end: still independent of the order
// of arrival.
//
// Why not keep every contribution and sort: the frame buffer then held the
// whole frame's contributions until its end (40 bytes each, 4.5 M of them on
// balls-5 at 1024x1024).
#pragma once
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "ray_job.h"

namespace rt {

constexpr int kFixedBits = 40;     // a component's resolution: 2^-40
constexpr double kFixedRange = double(uint64_t(1) << kFixedBits);  // 2^40: components at least this large are kept aside

// A colour in fixed point (units of 2^-kFixedBits), 128 bits per component.
struct FixedRgb {
    __int128 c[3] = {0, 0, 0};
};

// rgb in fixed point, each component rounded to the nearest unit (halves
// away from zero), if every component is finite and below kFixedRange in
// magnitude; false (out untouched) otherwise.
bool toFixed(const Vec3& rgb, FixedRgb& out);
// The fixed-point colour as doubles (rounded to nearest).
Vec3 toDouble(const FixedRgb& sum);

// The sums of n pixels, indexed 0..n-1 by their owner (a frame-buffer unit
// holds its own pixels; rtref one pixel at a time).
class PixelSums {
public:
    explicit PixelSums(size_t n = 0) : narrow_(n) {}
    size_t size() const { return narrow_.size(); }
    void add(size_t i, const Contribution& c);
    // Starts bringing pixel i's sum into the cache (i < size()), ahead of an add.
    void prefetch(size_t i) const { __builtin_prefetch(&narrow_[i], 1); }
    // Pixel i: its fixed-point sum plus, if any, the contributions kept
    // aside, summed in path-key order.
    Vec3 value(size_t i);
    // Every sum back to zero (for the next pixel or frame).
    void clear();

private:
    struct Narrow {
        int64_t c[3] = {0, 0, 0};
    };
    std::vector<Narrow> narrow_;                  // per pixel: what fits in 64 bits
    std::unordered_map<size_t, FixedRgb> wide_;   // per pixel, rarely: what would have overflowed it
    std::vector<std::pair<size_t, Contribution>> aside_;  // outside the fixed-point range
    bool sorted_ = true;  // aside_ in (index, key) order
};

}  // namespace rt
