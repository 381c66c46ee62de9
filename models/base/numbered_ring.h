// Items numbered 0, 1, 2, ... kept by their number in a ring, for a window
// of numbers that moves forward and grows: item n at n mod the ring's size,
// a power of two that doubles when the window outgrows it. Nothing moves or
// is dropped as the window moves on (a link's lanes, link.h, keep the
// records of the messages on the wire and when the last ones were taken
// in two of these).
#pragma once
#include <cstdint>
#include <memory>

namespace rt {

template <class T>
struct NumberedRing {
    std::unique_ptr<T[]> items;
    uint64_t mask = 0;  // size - 1 (no items before the first message)
    T& operator[](uint64_t n) { return items[n & mask]; }
    const T& operator[](uint64_t n) const { return items[n & mask]; }
    // Room for numbers from..to, keeping those from..to-1 (in place by their number).
    void fit(uint64_t from, uint64_t to) {
        const uint64_t need = to + 1 - from;
        if (items && need <= mask + 1) return;
        uint64_t size = items ? 2 * (mask + 1) : 4;
        while (size < need) size *= 2;
        std::unique_ptr<T[]> grown(new T[size]());
        for (uint64_t n = from; n < to; ++n) grown[n & (size - 1)] = items[n & mask];
        items = std::move(grown);
        mask = size - 1;
    }
};

}  // namespace rt
