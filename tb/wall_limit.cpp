#include "wall_limit.h"

#include <chrono>

#include "process/watchdog.h"

namespace rt {
namespace {

double limit = 0;

}  // namespace

void recordWallLimit(double seconds) { limit = seconds; }

double wallLimitSeconds() { return limit; }

double wallElapsed() { return std::chrono::duration<double>(std::chrono::steady_clock::now() - programStart()).count(); }

double wallLeft() {
    if (limit <= 0) return -1;
    const double left = limit - wallElapsed();
    return left > 0.001 ? left : 0.001;
}

bool wallPassed() { return limit > 0 && wallElapsed() >= limit; }

}  // namespace rt
