// How old the loads were that balancing decisions used, in intervals: a
// histogram at 1/1024 of an interval, so a node's memory for it is bounded
// by the range of ages seen, not by how many decisions it made (two per
// interval; a fine interval on a long frame made millions). The largest age
// is kept exactly; percentiles are within 1/2048 of an interval.
#pragma once

#include <cmath>
#include <cstdint>
#include <map>

namespace rt {

class AgeHistogram {
public:
    static constexpr double kBinsPerInterval = 1024;

    void add(double age) {
        ++bins_[uint64_t(std::llround(age * kBinsPerInterval))];
        ++count_;
        if (age > max_) max_ = age;
    }
    void merge(const AgeHistogram& o) {
        for (const auto& [bin, n] : o.bins_) bins_[bin] += n;
        count_ += o.count_;
        if (o.max_ > max_) max_ = o.max_;
    }
    uint64_t count() const { return count_; }
    size_t bins() const { return bins_.size(); }
    double max() const { return max_; }
    // The age of the decision at rank floor(p * count) in age order (p in
    // [0, 1)), as the centre of its bin.
    double percentile(double p) const {
        if (count_ == 0) return 0;
        uint64_t rank = uint64_t(p * double(count_));
        if (rank >= count_) rank = count_ - 1;
        for (const auto& [bin, n] : bins_) {
            if (rank < n) return double(bin) / kBinsPerInterval;
            rank -= n;
        }
        return max_;  // (not reached)
    }

private:
    std::map<uint64_t, uint64_t> bins_;  // bin -> decisions in it
    uint64_t count_ = 0;
    double max_ = 0;
};

}  // namespace rt
