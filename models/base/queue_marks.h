// A node's queue high-water mark: the most rays in hand and messages
// arrived on its links but not yet taken, at once. Counted in simulated
// time (messages that have arrived by a step's time), so it is the same in
// every exact mode.
//
// A node running ahead of the kernel (NodeParams::runAhead) does not see
// every message that arrives by its time yet: it records the depths of the
// steps it takes beyond what it sees (the step's time, its own work then,
// the messages it had taken by then) and settles them once its input as of
// then is all in its links: its own work, the messages taken since that
// had arrived by then (taken in arrival order), and those arrived by then
// still not taken.
//
// `Input` is what the node reads its links through (ArrivalQueue): it
// tells the messages not yet taken (unconsumed) and those arrived by a
// time (arrivedBy). Plain C++.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "base/units.h"

namespace rt {

class QueueDepthMarks {
public:
    explicit QueueDepthMarks(size_t& mark) : mark_(mark) {}

    // A message taken, which arrived at `arrival`.
    void taken(Picos arrival) {
        ++taken_;
        if (!deferred_.empty()) takenArrivals_.push_back(arrival);
    }
    // A step at `now` with `own` rays in hand, whose input the node sees.
    // The exact depth (a scan of the input links) only when it could set a
    // new mark: it is at most the rays in hand plus every message not taken.
    template <class Input>
    void step(Picos now, uint64_t own, const Input& in) {
        if (!deferred_.empty()) settle(in);  // (it sees now, so every earlier one)
        if (own + in.unconsumed() > mark_) mark_ = std::max(mark_, size_t(own + in.arrivedBy(now)));
    }
    // A step at `now` beyond what the node sees: settled later.
    void defer(Picos now, uint64_t own) {
        if (deferred_.empty()) takenBase_ = taken_;
        deferred_.push_back({now, own, taken_});
    }
    // The deferred depths, once every message that arrived by each is in the links.
    template <class Input>
    void settle(const Input& in) {
        const size_t unconsumed = in.unconsumed();
        for (const Deferred& d : deferred_) {
            const auto from = takenArrivals_.begin() + std::ptrdiff_t(d.taken - takenBase_);
            const auto takenSince = uint64_t(std::upper_bound(from, takenArrivals_.end(), d.t) - from);
            // (the scan of the links only when the depth could set a new mark, as in step)
            if (d.own + takenSince + unconsumed > mark_)
                mark_ = std::max(mark_, size_t(d.own + takenSince + in.arrivedBy(d.t)));
        }
        deferred_.clear();
        takenArrivals_.clear();
    }

    // The next frame: nothing deferred or taken (the mark is the node's figures').
    void restart() {
        deferred_.clear();
        takenArrivals_.clear();
        taken_ = takenBase_ = 0;
    }

private:
    struct Deferred {
        Picos t;
        uint64_t own, taken;
    };
    // (What a message taken reads and writes first, in one cache line.)
    size_t& mark_;
    uint64_t taken_ = 0;
    std::vector<Deferred> deferred_;
    std::vector<Picos> takenArrivals_;  // of the messages taken since the first deferred step, in the order taken
    uint64_t takenBase_ = 0;
};

}  // namespace rt
