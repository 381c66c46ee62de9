#include "memory_estimate.h"

#include <unistd.h>

#include <cstdio>

#include "scene_error.h"

namespace rt {

double physicalMemory() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    return pages > 0 && page > 0 ? double(pages) * double(page) : 0;
}

void refuseIfTooBig(const std::string& flag, double bytes) {
    const double have = physicalMemory();
    if (have <= 0 || bytes <= have) return;
    char buf[160];
    std::snprintf(buf, sizeof buf, ": needs at least %.1f GiB of memory, this machine has %.1f GiB", bytes / (1 << 30),
                  have / (1 << 30));
    throw SceneError(flag + buf);
}

}  // namespace rt
