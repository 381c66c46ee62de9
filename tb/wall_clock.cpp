#include "wall_clock.h"

namespace rt {
namespace {
const WallClock::Clock::time_point kStart = WallClock::Clock::now();
}

WallClock::Clock::time_point WallClock::processStart() { return kStart; }

double secondsBetween(WallClock::Clock::time_point from, WallClock::Clock::time_point to) {
    return std::chrono::duration<double>(to - from).count();
}

nlohmann::json WallClock::json() const {
    nlohmann::json j = {{"total_s", total()}, {"start_up_s", startUp}, {"frames_s", frames}, {"reference_runs_s", referenceRuns},
                        {"writing_s", writing}};
    if (calibration > 0) j["calibration_s"] = calibration;  // (--max-error)
    return j;
}

}  // namespace rt
