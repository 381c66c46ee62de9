// A monotone priority queue of (time, item): every time pushed is at least
// the last popped, which is how a process that runs in simulated time
// takes its events (the express relay, process/express_relay.h). A radix
// heap: an item lives in the bucket of the highest bit where its time
// differs from the last popped, so a push is O(1) and a pop moves each item
// at most once per bit; the buckets are plain vectors, read in order, where
// a binary heap of hundreds of thousands of events touched a cache line
// per level at every push and pop (balls-5 at 1024x1024 on 32x32x32).
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
    uint64_t top() const {
        size_t b = 0;
        while (buckets_[b].empty()) ++b;  // (size_ > 0)
        if (b == 0) return last_;
        uint64_t least = ~uint64_t(0);
        for (const Entry& e : buckets_[b]) least = std::min(least, e.t);
        return least;
    }
    void push(uint64_t t, Item item) {
        if (t < last_) throw std::logic_error("radix heap: a time before the last popped");
        buckets_[bucketOf(t)].push_back({t, std::move(item)});
        ++size_;
    }
    // Every item of the smallest time, appended to `out` (the heap must not be empty).
    void popTies(std::vector<Item>& out) {
        settle();
        for (Entry& e : buckets_[0]) out.push_back(std::move(e.item));
        size_ -= buckets_[0].size();
        buckets_[0].clear();
    }
    void clear() {
        for (auto& b : buckets_) b.clear();
        size_ = 0;
        last_ = 0;
    }

private:
    struct Entry {
        uint64_t t;
        Item item;
    };
    size_t bucketOf(uint64_t t) const { return t == last_ ? 0 : size_t(64 - __builtin_clzll(t ^ last_)); }
    // Makes bucket 0 hold the items of the smallest time (last_).
    void settle() {
        if (!buckets_[0].empty()) return;
        size_t b = 1;
        while (buckets_[b].empty()) ++b;  // (size_ > 0)
        uint64_t least = ~uint64_t(0);
        for (const Entry& e : buckets_[b]) least = std::min(least, e.t);
        last_ = least;
        for (Entry& e : buckets_[b]) buckets_[bucketOf(e.t)].push_back(std::move(e));
        buckets_[b].clear();
    }
    std::array<std::vector<Entry>, 65> buckets_;
    size_t size_ = 0;
    uint64_t last_ = 0;
};

}  // namespace rt
