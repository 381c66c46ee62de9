// Stops that stop (doc/robustness.md, "Stops"): Ctrl-C, SIGTERM and
// --watchdog-wall take effect within a second wherever rtsim is.
//  - In start-up (the flags and the scene read, the scene binned, the
//    machine built) nothing is worth keeping: rtsim ends at once from the
//    signal handler, its temporary files removed, with 128 + N (3 for the
//    wall-clock limit) and one line.
//  - While the machine runs, the watchdog stops it at its next wake (every
//    millisecond of simulated time), with the report and the VCD so far
//    (models/process/watchdog.h).
//  - Between the frames of a sequence and while child runs go (the
//    reference runs: "orderly" stops), the frame running is stopped by its
//    watchdog, each child is told once; rtsim then writes what it has: the
//    frames so far, or the finished frame's outputs.
//  - A second signal ends rtsim at once, as in start-up.
// The wall-clock limit counts from rtsim's start; a child run gets what is
// left of it.
#pragma once

#include "wall_limit.h"

namespace rt {

// Installs the handlers (first thing in main) and starts the wall clock.
void installStopHandlers();
// After the flags are read: --watchdog-wall's limit in seconds (0: none);
// a timer ends a start-up that passes it.
void setWallLimit(double seconds);
// (wallLeft, wallPassed: wall_limit.h)

// While one lives, a stop is orderly (see above).
class OrderlyStops {
public:
    OrderlyStops();
    ~OrderlyStops();
    OrderlyStops(const OrderlyStops&) = delete;
    OrderlyStops& operator=(const OrderlyStops&) = delete;

private:
    int before_;
};

}  // namespace rt
