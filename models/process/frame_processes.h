// A frame's processes (the modules' own in the first frame, then those
// spawned for each later one: spawn.h), held from their start to the next
// frame's: SystemC deletes a process when its last handle goes, not when
// it is ended. Both ending and letting go run newest first, because SystemC
// finds a process in its list of processes from the newest on: oldest
// first, each would take a search of every process, quadratic in the
// nodes (at 32x32x32 seconds of a run).
#pragma once
#include <vector>

#include <systemc>

namespace rt {

class FrameProcesses {
public:
    FrameProcesses() = default;
    FrameProcesses(const FrameProcesses&) = delete;
    FrameProcesses& operator=(const FrameProcesses&) = delete;
    ~FrameProcesses() { clear(); }

    // The next process, in the order the modules make theirs.
    void add(sc_core::sc_process_handle h) { held_.push_back(std::move(h)); }
    // Ends each (but `self`, the caller's) not ended yet.
    void endAllBut(const sc_core::sc_process_handle& self) {
        for (size_t i = held_.size(); i-- > 0;) {
            sc_core::sc_process_handle& h = held_[i];
            if (h.valid() && h != self && !h.terminated()) h.kill();
        }
    }
    // Lets them go (SystemC then deletes the ended ones).
    void clear() {
        while (!held_.empty()) held_.pop_back();
    }

private:
    std::vector<sc_core::sc_process_handle> held_;  // oldest first
};

}  // namespace rt
