// What the watchdog (machine.h) watches: the latest simulated time at which
// a ray, a contribution or credit moved (a node traced a ray, or a link took
// a ray, contribution, credit or frame-buffer message). Balancing messages
// do not count: a run whose only traffic is load reports is stuck.
//
// Each mark also looks (one load of a flag) for a stop asked from outside:
// a signal or the wall-clock limit, set by rtsim's handlers (tb/stops.h).
// Then it wakes the watchdog at once rather than at its next period, which
// in a large mesh can be many seconds of wall-clock time away.
#pragma once
#include <csignal>

#include <systemc>

#include "base/units.h"

namespace rt {

// Set by a signal handler: the signal that asks the run to stop; the
// wall-clock limit reached (watchdog.cpp defines them).
extern volatile std::sig_atomic_t stopSignal, wallExpired;

struct Progress {
    Picos last = 0;
    sc_core::sc_event* wake = nullptr;  // the watchdog's
    bool woken = false;
    void mark(Picos t) {
        if (t > last) last = t;
        poll();
    }
    // The look for a stop alone, where no ray moved (a balancing interval):
    // on links of 2 B/s a ray takes a minute of simulated time, the
    // watchdog's period is as long, and the intervals between took 48 s of
    // wall-clock time to answer a SIGTERM.
    void poll() {
        if ((stopSignal | wallExpired) && wake && !woken) {
            woken = true;
            wake->notify(sc_core::SC_ZERO_TIME);
        }
    }
};

}  // namespace rt
