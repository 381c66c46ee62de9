// Where along the progress axis a node's tracing work happened over a frame,
// for `resplit`'s next planes (between_frames.h): fine bins fixed in the
// world (kBinsPerBox per initial box thickness, so a re-split can place a
// plane within a thin box of a crowded layer), stored only over the span the
// node traced (its box, and what it slid over), grown as steps land outside.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace rt {

class WorkByPosition {
public:
    static constexpr int kBinsPerBox = 128;
    WorkByPosition() = default;
    // The world along the axis from `from`, `boxes` initial boxes long.
    WorkByPosition(double from, double to, int boxes) : from_(from), width_((to - from) / double(kBinsPerBox * boxes)) {}

    // `work` ps at `where` (NaN or outside the world: clamped to its ends by the bins' range).
    void add(double where, double work) {
        if (!(width_ > 0) || !std::isfinite(where)) return;
        const int64_t k = int64_t(std::floor((where - from_) / width_));
        if (bins_.empty()) first_ = k;
        if (k < first_) {
            bins_.insert(bins_.begin(), size_t(first_ - k), 0.0);
            first_ = k;
        }
        if (k >= first_ + int64_t(bins_.size())) bins_.resize(size_t(k - first_ + 1), 0.0);
        bins_[size_t(k - first_)] += work;
    }
    double from() const { return from_; }
    double binWidth() const { return width_; }
    int64_t firstBin() const { return first_; }          // bin k spans from + [k, k + 1) x binWidth
    const std::vector<double>& bins() const { return bins_; }  // from firstBin on, in ps

private:
    double from_ = 0, width_ = 0;
    int64_t first_ = 0;
    std::vector<double> bins_;
};

}  // namespace rt
