// How a process (a node or the host) keeps its local time in step with the
// kernel's: the one place where time synchronisation is decided
// (doc/time.md, "Local time and temporal decoupling").
//
//   --quantum 0  (exact) wait for the kernel after every step.
//   --quantum Q  run ahead of the kernel, and wait for it once Q ahead (the
//                TLM-2.0 quantum keeper). Still exact while Q is at most the
//                process's lookahead: the soonest a message not yet sent can
//                arrive at it (its input links' latency plus the smallest
//                message's time on their wire; Link::lookahead).
//   --quantum lookahead (the default): each process's own lookahead; a
//                node without a dynamic policy then synchronises only when
//                it must read input it does not see yet (NodeParams::
//                runAhead, Node::takeWork), not after every step.
//
// In both, a process that waits for input waits until the kernel has caught
// up with it at least (one wait, ArrivalQueue::waitForInput); a step that
// leaves it with nothing to do goes straight into that wait instead of
// synchronising first. With a quantum, a process whose next input
// is already on its way and due within the quantum idles until it arrives
// without waiting for the kernel (mayIdleUntil). Most of a node's time is
// idle, so this is what makes a quantum pay: without these two, a process
// would synchronise with the kernel at every idle step (doc/history.md,
// "Figures behind the code's comments").
//
// The processes are method processes (SC_METHOD): a wait is the process
// returning with its next activation armed (next_trigger). An activation
// costs about 28 ns against a thread switch's 36 to 45 ns in a
// micro-benchmark, and with 4,096 nodes there are no stacks to switch
// between (doc/exploration.md).
#pragma once
#include <systemc>

#include "base/frame_clock.h"
#include "config/machine_config.h"

namespace rt {

class TimeKeeper {
public:
    explicit TimeKeeper(Picos quantum) : quantum_(quantum), sim_(sc_core::sc_get_curr_simcontext()) {}
    // Before the simulation starts: the process's own lookahead
    // (MachineConfig::lookaheadQuantum).
    void setQuantum(Picos quantum) { quantum_ = quantum; }

    // After a step that took `cost` and ended at local time `now`: whether
    // the process must let the kernel catch up before it goes on.
    bool mustSync(Picos now, Picos cost) const {
        if (quantum_ == 0) return cost > 0;
        const Picos k = kernel();
        return now > k && now - k >= quantum_;
    }

    // Lets the kernel catch up with local time `now`: the calling (method)
    // process runs next then.
    void syncTo(Picos now) const { sc_core::next_trigger(sc_core::sc_time::from_value(now - kernel())); }

    // A process with nothing to do until `t` (a known arrival or deadline)
    // may move its local time there without waiting for the kernel, if `t`
    // lies within the quantum: the same licence as running ahead by working.
    // Exact under the lookahead quantum, since no message still to be sent
    // can arrive before kernel time + lookahead.
    bool mayIdleUntil(Picos t) const {
        const Picos k = kernel();
        return quantum_ > 0 && t != ~Picos(0) && t >= k && t - k < quantum_;
    }

    bool decoupled() const { return quantum_ > 0; }

    // Whether every message that arrives by `t` is already in the process's
    // links: true while `t` is less than the quantum ahead of the kernel,
    // exact when the quantum is the process's lookahead (no message still
    // to be sent arrives sooner).
    bool sees(Picos t) const { return t < kernel() + quantum_; }

private:
    // The kernel's time, read every step: from the simulation context itself
    // (an inline read), not through sc_time_stamp() (a call into the library).
    Picos kernel() const { return sim_->time_stamp().value() - frameOrigin; }

    Picos quantum_;
    const sc_core::sc_simcontext* sim_;
};

}  // namespace rt
