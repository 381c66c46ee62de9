// The watchdog (--watchdog, --watchdog-wall; doc/robustness.md, "The
// watchdog and bad input"): a method process that wakes every span of
// simulated time, or every millisecond (or a thousandth of the span, if
// longer) if that is sooner, so at most a few times in most frames and
// often enough to see the wall clock; and stops a run in which nothing
// moved for a whole span, that has run past the wall-clock limit, or that a
// signal asked to stop. A stuck run with balancing never ends by itself
// (the nodes keep waking for their intervals), and without balancing it
// ends only with the kernel out of events.
#pragma once
#include <chrono>
#include <csignal>
#include <functional>
#include <string>

#include <systemc>

#include "base/frame_clock.h"
#include "base/progress.h"
#include "base/units.h"

namespace rt {

// A signal (SIGINT, SIGTERM) asks the running machine to stop: the watchdog
// sees it at its next wake and stops the run as it would a stuck one, with
// the report and VCD so far ("interrupted by signal N"). Set from a signal
// handler (tb/rtsim.cpp), hence a plain global.
extern volatile std::sig_atomic_t stopSignal;
// Set by a timer (tb/stops.h): --watchdog-wall has passed.
extern volatile std::sig_atomic_t wallExpired;
// Set at the watchdog's first wake: the machine runs, and a stop is the
// watchdog's to make (before it, tb/stops.h ends the program at once).
extern volatile std::sig_atomic_t simulationRunning;
// When the program started (its first call; rtsim makes it first thing):
// --watchdog-wall counts from here, start-up included.
std::chrono::steady_clock::time_point programStart();

class Watchdog : public sc_core::sc_module {
public:
    // What it asks of the machine it watches.
    struct Machine {
        std::function<bool()> frameDone;
        std::function<void()> flushTrace;       // the waveform so far, on disk
        std::function<std::string()> whoHolds;  // where the work is: the nodes still holding any
        std::function<void()> endProcesses;     // every process but the caller's
    };
    SC_HAS_PROCESS(Watchdog);
    // `span`: simulated time without progress before it stops the run;
    // `wallLimit`: seconds of wall-clock time since programStart() (0: none).
    Watchdog(sc_core::sc_module_name name, Picos span, double wallLimit, Machine machine);

    // Marked by the nodes and links whenever a ray, contribution or credit moves.
    Progress& progress() { return progress_; }
    // Why and when it stopped the run (empty: it did not).
    const std::string& stall() const { return stall_; }
    Picos stalledAt() const { return stalledAt_; }
    // The next frame of a sequence: watching afresh, in a new process
    // (spawn.h) named after `frame`.
    sc_core::sc_process_handle restart(int frame);
    void quiet() { wakeNow_.cancel(); }  // the frame is over: no wake still to come

private:
    void watch();
    std::string whyStop(Picos now) const;  // empty: no reason to

    Picos span_, period_;
    double wallLimit_;
    Machine machine_;
    bool started_ = false;
    Progress progress_;
    sc_core::sc_event wakeNow_;  // a stop asked from outside (progress.h)
    std::string stall_;
    Picos stalledAt_ = 0;
};

}  // namespace rt
