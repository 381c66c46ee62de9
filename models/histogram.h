// A distribution of non-negative integers (message latencies in ps, load
// ages in 1/1024 of an interval) for percentiles, in memory bounded by the
// range of the values rather than their number: a machine has tens of
// thousands of links and a frame millions of messages.
//
// Exact while it has seen at most kExact distinct values (so a small run's
// percentiles are the values themselves, which tests compare with hand
// computations); after that, values share bins of 2^kBits per octave
// (log-linear, as HdrHistogram does), a percentile is its bin's centre and
// is within 1/2^(kBits+1) (0.8 %) of the true value. The largest value is
// kept exactly.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace rt {

class Histogram {
public:
    static constexpr size_t kExact = 64;  // distinct values kept exactly
    static constexpr int kBits = 6;       // then 64 bins per octave

    void add(uint64_t v, uint64_t n = 1) {
        const uint64_t key = coarse_ ? binOf(v) : v;
        if (last_ < bins_.size() && bins_[last_].first == key) {  // (a link's messages often take the same time)
            bins_[last_].second += n;
        } else {
            auto it = std::lower_bound(bins_.begin(), bins_.end(), key, [](const auto& b, uint64_t k) { return b.first < k; });
            if (it != bins_.end() && it->first == key) it->second += n;
            else it = bins_.insert(it, {key, n});
            last_ = size_t(it - bins_.begin());
        }
        count_ += n;
        max_ = std::max(max_, v);
        if (!coarse_ && bins_.size() > kExact) coarsen();
    }
    void merge(const Histogram& o) {
        if (o.coarse_ && !coarse_) coarsen();
        for (const auto& [key, n] : o.bins_) add(key, n);  // (a coarse key is its own bin)
        max_ = std::max(max_, o.max_);
    }
    uint64_t count() const { return count_; }
    size_t bins() const { return bins_.size(); }
    uint64_t max() const { return max_; }
    // The value at rank floor(p * count) in order (p in [0, 1]): exact, or
    // its bin's centre (0 if empty).
    double percentile(double p) const {
        if (count_ == 0) return 0;
        uint64_t rank = std::min(count_ - 1, uint64_t(p * double(count_)));
        for (const auto& [key, n] : bins_) {
            if (rank < n) return coarse_ ? double(key) + double(width(key) - 1) / 2 : double(key);
            rank -= n;
        }
        return double(max_);  // (not reached)
    }

private:
    // The bin of v: v with all but its kBits + 1 leading bits cleared.
    static uint64_t width(uint64_t v) {
        const int msb = v ? 63 - __builtin_clzll(v) : 0;  // (once per message: no loop)
        return uint64_t(1) << std::max(0, msb - kBits);
    }
    static uint64_t binOf(uint64_t v) { return v & ~(width(v) - 1); }
    void coarsen() {
        coarse_ = true;
        std::vector<std::pair<uint64_t, uint64_t>> old;
        old.swap(bins_);
        last_ = ~size_t(0);
        count_ = 0;
        const uint64_t m = max_;
        for (const auto& [v, n] : old) add(v, n);
        max_ = m;
    }

    std::vector<std::pair<uint64_t, uint64_t>> bins_;  // (value or bin, count), sorted
    uint64_t count_ = 0, max_ = 0;
    size_t last_ = ~size_t(0);  // the bin the last value went to
    bool coarse_ = false;
};

}  // namespace rt
