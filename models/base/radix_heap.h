// A monotone priority queue of (time, item): every time pushed is at least
// the last popped, which is how a process that runs in simulated time
// takes its events (the express relay, process/express_relay.h). A radix
// heap on hexadecimal digits: an item lives in the bucket of the highest
// digit where its time differs from the last popped, and of that digit's
// value, so a push is O(1) and a pop moves each item at most once per digit:
// a quarter as many moves at most as on binary digits, where moving items
// down the buckets was the largest part of the relay's own instructions
// (doc/history.md, "Figures behind the code's comments"). The buckets are
// plain vectors, read in order, where a binary heap of hundreds of
// thousands of events touched a cache line per level at every push and pop.
// Items of one time come out together, in no particular order: the caller
// orders them (popTies). After a pop, the times pushed must be at least the
// one popped, though they may be less than the smallest still queued.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace rt {

template <class Item>
class RadixHeap {
public:
    bool empty() const { return size_ == 0; }
    size_t size() const { return size_; }
    // The smallest time queued (the heap must not be empty). It changes
    // nothing: a time may still be pushed that is smaller than it (but not
    // than the last popped).
    // (Each bucket keeps its least time as items come in, so the top is
    // found without reading the bucket: the relay asks for it before every
    // pop, and a bucket far from the last popped holds thousands.)
    uint64_t top() const {
        const size_t b = lowest();  // (size_ > 0)
        return b == 0 ? last_ : least_[b];
    }
    void push(uint64_t t, Item item) {
        if (t < last_) throw std::logic_error("radix heap: a time before the last popped");
        add(bucketOf(t), {t, std::move(item)});
        ++size_;
    }
    // Every item of the smallest time, appended to `out` (the heap must not be empty).
    void popTies(std::vector<Item>& out) {
        settle();
        for (Entry& e : buckets_[0]) out.push_back(std::move(e.item));
        size_ -= buckets_[0].size();
        empty(0);
    }
    void clear() {
        for (size_t b = 0; b < buckets_.size(); ++b) empty(b);
        size_ = 0;
        last_ = 0;
    }

private:
    struct Entry {
        uint64_t t;
        Item item;
    };
    // Bucket 0: the last popped time; then by the highest digit that
    // differs from it, and the time's value there (greater than the last's):
    // every time in a bucket is less than every time in a later one.
    static constexpr int kDigitBits = 4, kRadix = 1 << kDigitBits;
    static constexpr size_t kBuckets = 1 + size_t(64 / kDigitBits) * kRadix;
    size_t bucketOf(uint64_t t) const {
        if (t == last_) return 0;
        const int level = (63 - __builtin_clzll(t ^ last_)) / kDigitBits;
        return 1 + size_t(level) * kRadix + size_t((t >> (level * kDigitBits)) & (kRadix - 1));
    }
    // The lowest bucket that holds an item (the heap must not be empty).
    size_t lowest() const {
        size_t w = 0;
        while (!full_[w]) ++w;
        return 64 * w + size_t(__builtin_ctzll(full_[w]));
    }
    void add(size_t b, Entry&& e) {
        if (buckets_[b].empty()) least_[b] = e.t;
        else least_[b] = std::min(least_[b], e.t);
        buckets_[b].push_back(std::move(e));
        full_[b / 64] |= uint64_t(1) << (b % 64);
    }
    void empty(size_t b) {
        buckets_[b].clear();
        full_[b / 64] &= ~(uint64_t(1) << (b % 64));
    }
    // Makes bucket 0 hold the items of the smallest time (last_).
    void settle() {
        if (!buckets_[0].empty()) return;
        const size_t b = lowest();  // (size_ > 0; not 0)
        last_ = least_[b];
        for (Entry& e : buckets_[b]) add(bucketOf(e.t), std::move(e));  // (each to a lower bucket: its time is closer to last_)
        empty(b);
    }
    std::array<std::vector<Entry>, kBuckets> buckets_;
    std::array<uint64_t, kBuckets> least_{};             // bucket b's least time, while it holds any
    std::array<uint64_t, (kBuckets + 63) / 64> full_{};  // bit b % 64 of word b / 64: bucket b holds items
    size_t size_ = 0;
    uint64_t last_ = 0;
};

}  // namespace rt
