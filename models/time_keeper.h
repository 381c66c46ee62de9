// How a process (a node or the host) keeps its local time in step with the
// kernel's: the one place where time synchronisation is decided
// (doc/machine.md, "Local time and temporal decoupling").
//
//   --quantum 0  (exact) wait for the kernel after every step.
//   --quantum Q  run ahead of the kernel, and wait for it once Q ahead (the
//                TLM-2.0 quantum keeper). Still exact while Q is at most the
//                smallest link latency (the lookahead).
//
// In both, a process catches up with the kernel before it waits for input,
// so the kernel can move on.
#pragma once
#include <systemc>

#include "machine_config.h"

namespace rt {

class TimeKeeper {
public:
    explicit TimeKeeper(Picos quantum) : quantum_(quantum) {}

    // After a step that took `cost` and ended at local time `now`.
    void afterStep(Picos now, Picos cost) const {
        if (quantum_ == 0) {
            if (cost) sc_core::wait(sc_core::sc_time::from_value(cost));
            return;
        }
        const Picos k = kernel();
        if (now > k && now - k >= quantum_) sc_core::wait(sc_core::sc_time::from_value(now - k));
    }

    // Before waiting for input: the kernel catches up with `now`.
    void catchUp(Picos now) const {
        const Picos k = kernel();
        if (now > k) sc_core::wait(sc_core::sc_time::from_value(now - k));
    }

    bool decoupled() const { return quantum_ > 0; }

private:
    static Picos kernel() { return sc_core::sc_time_stamp().value(); }

    Picos quantum_;
};

}  // namespace rt
