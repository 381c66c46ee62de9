#include "process/watchdog.h"

#include <algorithm>
#include <sstream>

#include "process/spawn.h"

namespace rt {

volatile std::sig_atomic_t stopSignal = 0;
volatile std::sig_atomic_t simulationRunning = 0;
volatile std::sig_atomic_t wallExpired = 0;

std::chrono::steady_clock::time_point programStart() {
    static const std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    return start;
}

Watchdog::Watchdog(sc_core::sc_module_name name, Picos span, double wallLimit, Machine machine)
    : sc_module(name),
      span_(span),
      period_(std::min<Picos>(span, std::max<Picos>(1000000000, span / 1000))),
      wallLimit_(wallLimit),
      machine_(std::move(machine)) {
    progress_.wake = &wakeNow_;
    SC_METHOD(watch);
}

void Watchdog::watch() {
    const auto wake = [&] { sc_core::next_trigger(sc_core::sc_time::from_value(period_), wakeNow_); };
    if (!started_) {  // its first activation, at time 0
        started_ = true;
        simulationRunning = 1;
        wake();
        return;
    }
    if (machine_.frameDone()) return;
    machine_.flushTrace();
    const Picos now = frameClock();
    const std::string why = whyStop(now);
    if (why.empty()) {
        wake();
        return;
    }
    stalledAt_ = now;
    stall_ = why + "; " + machine_.whoHolds();
    machine_.endProcesses();  // (with nothing left to run, the simulation returns)
}

sc_core::sc_process_handle Watchdog::restart(int frame) {
    quiet();
    started_ = false;
    progress_ = Progress{};
    progress_.wake = &wakeNow_;
    stall_.clear();
    stalledAt_ = 0;
    return spawnMethod([this] { watch(); }, *this, frame);
}

std::string Watchdog::whyStop(Picos now) const {
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - programStart()).count();
    std::ostringstream why;
    if (stopSignal) {
        why << "interrupted by signal " << int(stopSignal) << " at " << formatTime(now) << " of simulated time";
    } else if (now >= progress_.last + span_) {
        why << "no ray, contribution or credit moved for " << formatTime(now - progress_.last)
            << " of simulated time (since " << formatTime(progress_.last) << ")";
    } else if (wallExpired || (wallLimit_ > 0 && wall >= wallLimit_)) {
        why << "the wall-clock limit of " << wallLimit_ << " s was reached at " << formatTime(now)
            << " of simulated time";
    }
    return why.str();
}

}  // namespace rt
