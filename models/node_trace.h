// What the VCD shows of one node: value changes of busy, wait and queue
// depth, recorded only for traced nodes (tracing is switched on per node).
#pragma once
#include <cstdint>
#include <vector>

#include "units.h"

namespace rt {

struct Change {
    Picos t;
    int64_t v;
};

struct NodeTrace {
    std::vector<Change> busy, wait, queue;
    static void record(std::vector<Change>& s, Picos t, int64_t v) {
        if (!s.empty() && s.back().v == v) return;
        if (!s.empty() && s.back().t == t) {  // several changes at one instant: the last one stands
            s.back().v = v;
            if (s.size() >= 2 && s[s.size() - 2].v == v) s.pop_back();
            return;
        }
        s.push_back({t, v});
    }
};

}  // namespace rt
