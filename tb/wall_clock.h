// The run's wall-clock time and where it went: the summary's "wall clock"
// line and the report's `wall_clock` (doc/report.md). The parts follow each
// other, so they add up to the whole:
//  - start-up: the process to its first frame (the command line, the scene,
//    the checks) and building the machine (elaboration, once for all the
//    frames);
//  - calibration: --max-error's calibration frames (0 without);
//  - frames: the frames simulated (with --frames K, the K - 1 before the
//    last too, and the host phases between them; --trace-nodes busiest's
//    first pass of the last frame);
//  - reference runs: the 1x1x1 baseline and the balancing comparison, two
//    child processes at once (0 with --no-baseline);
//  - writing: assembling the report and writing the outputs (the image, the
//    report, the mesh map, the renames).
#pragma once
#include <chrono>

#include <nlohmann/json.hpp>

namespace rt {

class WallClock {
public:
    using Clock = std::chrono::steady_clock;
    // Now, as a mark between parts.
    static Clock::time_point now() { return Clock::now(); }
    // The process's start (at static initialisation, before sc_main).
    static Clock::time_point processStart();

    double startUp = 0, calibration = 0, frames = 0, referenceRuns = 0, writing = 0;  // seconds
    double total() const { return startUp + calibration + frames + referenceRuns + writing; }
    nlohmann::json json() const;
};

double secondsBetween(WallClock::Clock::time_point from, WallClock::Clock::time_point to);

}  // namespace rt
