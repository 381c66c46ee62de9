// rtsim's wall-clock limit (--watchdog-wall), counted from the
// program's start: the stops arm a timer on it (stops.h), and a child run
// gets what is left of it (subprocess.h).
#pragma once

namespace rt {

// Records the limit in seconds (0: none); stops.h's setWallLimit also arms
// the timer that ends a start-up past it.
void recordWallLimit(double seconds);
double wallLimitSeconds();
// Seconds since the program started.
double wallElapsed();
// Seconds left of the wall-clock limit (at least 1 ms); -1 without one.
double wallLeft();
// Whether the wall-clock limit has passed.
bool wallPassed();

}  // namespace rt
