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
// kept exactly. The exact values are a sorted list; the coarse bins are an
// array of counts indexed by bin, from the lowest bin seen to the highest
// (8 bytes a bin, 512 an octave), so a value finds its bin without a search.
//
// Single values wait in a few slots inside the object and go into the bins
// a handful at a time (sorted while exact; coarse bins need no search, and
// sorting latencies mispredicted): a link adds one per message, and its bins
// are a block of their own that a link not used for a while has out of cache
// (the bin search was a third of Link::take on the 16x16x16 mesh). The bins
// do not depend on the order values come in (exact values are a set; coarse
// ones are v's bin whenever they came), so the figures are the same.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

namespace rt {

class Histogram {
public:
    static constexpr size_t kExact = 64;  // distinct values kept exactly
    static constexpr int kBits = 6;       // then 64 bins per octave

    void add(uint64_t v, uint64_t n = 1) {
        if (n == 1) {
            waiting_[waitingCount_++] = v;
            if (waitingCount_ == kWaiting) settle();
            return;
        }
        settle();
        insert(v, n);
    }
    void merge(const Histogram& o) {
        settle();
        o.settle();
        if (o.coarse_ && !coarse_) coarsen();
        o.forEachBin([&](uint64_t key, uint64_t n) { insert(key, n); });  // (a coarse key is its own bin)
        max_ = std::max(max_, o.max_);
    }
    uint64_t count() const { return count_ + waitingCount_; }
    size_t bins() const {
        settle();
        return coarse_ ? nonEmpty_ : bins_.size();
    }
    uint64_t max() const {
        settle();
        return max_;
    }
    // The value at rank floor(p * count) in order (p in [0, 1]): exact, or
    // its bin's centre (0 if empty).
    double percentile(double p) const {
        settle();
        if (count_ == 0) return 0;
        uint64_t rank = std::min(count_ - 1, uint64_t(p * double(count_)));
        double value = double(max_);  // (not kept)
        forEachBin([&](uint64_t key, uint64_t n) {
            if (rank < n) {
                value = coarse_ ? double(key) + double(width(key) - 1) / 2 : double(key);
                return false;
            }
            rank -= n;
            return true;
        });
        return value;
    }

private:
    static constexpr uint8_t kWaiting = 8;
    // The waiting values into the bins, equal ones as one.
    // (const: the figures are the same before and after, hence the mutable members)
    void settle() const {
        if (!waitingCount_) return;
        const uint8_t k = waitingCount_;
        waitingCount_ = 0;
        if (coarse_) {  // a value's bin is found without a search: no order needed (sorting mispredicted)
            for (uint8_t i = 0; i < k; ++i) insert(waiting_[i], 1);
            return;
        }
        std::sort(waiting_.begin(), waiting_.begin() + k);
        for (uint8_t i = 0; i < k;) {
            uint8_t j = i + 1;
            while (j < k && waiting_[j] == waiting_[i]) ++j;
            insert(waiting_[i], j - i);
            i = j;
        }
    }
    // Calls f(key, count) for each bin holding values, in order, until f
    // returns false (if it returns a bool).
    template <class F>
    void forEachBin(F&& f) const {
        auto call = [&](uint64_t key, uint64_t n) {
            if constexpr (std::is_same_v<decltype(f(key, n)), bool>) return f(key, n);
            else return f(key, n), true;
        };
        if (!coarse_) {
            for (const auto& [key, n] : bins_)
                if (!call(key, n)) return;
            return;
        }
        for (size_t i = 0; i < dense_.size(); ++i)
            if (dense_[i] && !call(keyOf(base_ + i), dense_[i])) return;
    }

    void insert(uint64_t v, uint64_t n) const {
        if (coarse_) {
            addToBin(indexOf(v), n);
            count_ += n;
            max_ = std::max(max_, v);
            return;
        }
        const uint64_t key = v;
        if (last_ < bins_.size() && bins_[last_].first == key) {  // (a link's messages often take the same time)
            bins_[last_].second += n;
        } else {
            // Settled values come sorted, so the bin is usually just past the
            // last one: gallop from there (1, 2, 4, ... bins on) before the
            // binary search, which touches a few bins near it instead of
            // ones spread over the whole list (cache misses on a link not
            // used for a while).
            // A batch's first value is often a little below the last one's,
            // so it gallops back the same way.
            auto lo = bins_.begin(), hi = bins_.end();
            if (last_ < bins_.size() && bins_[last_].first < key) {
                size_t step = 1, from = last_ + 1;
                while (from + step - 1 < bins_.size() && bins_[from + step - 1].first < key) {
                    from += step;
                    step *= 2;
                }
                lo = bins_.begin() + long(from);
                hi = bins_.begin() + long(std::min(bins_.size(), from + step));
            } else if (last_ < bins_.size()) {  // key < bins_[last_]: the bin is at or below last_
                size_t step = 1, to = last_;    // bins_[to] >= key
                while (to >= step && bins_[to - step].first >= key) {
                    to -= step;
                    step *= 2;
                }
                lo = bins_.begin() + long(to >= step ? to - step + 1 : 0);
                hi = bins_.begin() + long(to + 1);
            }
            auto it = std::lower_bound(lo, hi, key, [](const auto& b, uint64_t k) { return b.first < k; });
            if (it != bins_.end() && it->first == key) it->second += n;
            else it = bins_.insert(it, {key, n});
            last_ = size_t(it - bins_.begin());
        }
        count_ += n;
        max_ = std::max(max_, v);
        if (bins_.size() > kExact) coarsen();
    }
    // A coarse bin's count: the array grows to take in a bin below or above it.
    void addToBin(size_t index, uint64_t n) const {
        if (dense_.empty()) {
            base_ = uint32_t(index);
            dense_.assign(1, 0);
        } else if (index < base_) {
            dense_.insert(dense_.begin(), base_ - index, 0);
            base_ = uint32_t(index);
        } else if (index - base_ >= dense_.size()) {
            dense_.resize(index - base_ + 1, 0);
        }
        uint64_t& c = dense_[index - base_];
        nonEmpty_ += c == 0;
        c += n;
    }

    // The bin of v: v with all but its kBits + 1 leading bits cleared.
    static uint64_t width(uint64_t v) {
        const int msb = v ? 63 - __builtin_clzll(v) : 0;  // (once per message: no loop)
        return uint64_t(1) << std::max(0, msb - kBits);
    }
    // Bins numbered in order: values below 2^(kBits+1) are their own bins,
    // then 2^kBits bins per octave.
    static size_t indexOf(uint64_t v) {
        const int msb = v ? 63 - __builtin_clzll(v) : 0;
        if (msb <= kBits) return size_t(v);
        const int shift = msb - kBits;
        return (size_t(shift) << kBits) + size_t(v >> shift);
    }
    static uint64_t keyOf(size_t index) {  // the lowest value of bin `index`
        if (index < (size_t(2) << kBits)) return index;
        const size_t shift = (index >> kBits) - 1;
        return uint64_t(index - (shift << kBits)) << shift;
    }
    void coarsen() const {
        coarse_ = true;
        std::vector<std::pair<uint64_t, uint64_t>> old;
        old.swap(bins_);
        last_ = ~size_t(0);
        count_ = 0;
        const uint64_t m = max_;
        for (const auto& [v, n] : old) insert(v, n);
        max_ = m;
    }

    // (What a value added touches first, then what settling it touches:
    // a link adds one per message, from a block out of cache.)
    mutable uint8_t waitingCount_ = 0;
    mutable bool coarse_ = false;
    mutable std::array<uint64_t, kWaiting> waiting_;  // single values not yet in the bins
    mutable std::vector<uint64_t> dense_;  // coarse: the counts of bins base_, base_ + 1, ...
    mutable uint32_t base_ = 0, nonEmpty_ = 0;  // (a bin's index is below 2^(kBits + 7))
    mutable uint64_t count_ = 0, max_ = 0;  // of the values in the bins
    mutable std::vector<std::pair<uint64_t, uint64_t>> bins_;  // exact: (value, count), sorted
    mutable size_t last_ = ~size_t(0);      // the bin the last value went to
};

}  // namespace rt
