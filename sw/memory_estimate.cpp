#include "memory_estimate.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "scene_error.h"

namespace rt {
namespace {

constexpr double kGiB = double(1 << 30);

// A cgroup file's limit in bytes: 0 for "max" (v2), v1's "unlimited" (the
// largest page-aligned int64, about 2^63), or anything unreadable.
double limitIn(const std::string& path) {
    std::ifstream f(path);
    std::string text;
    if (!(f >> text) || text == "max") return 0;
    try {
        const double v = std::stod(text);
        return v > 0 && v < 0x1p62 ? v : 0;
    } catch (const std::exception&) {
        return 0;
    }
}

// `path` ("/a/b") and its parents up to "/": the cgroup and its ancestors.
std::string parentOf(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    return slash == 0 || slash == std::string::npos ? "/" : path.substr(0, slash);
}

// The least limit named `name` in `base` + path and its parents.
double leastUp(const std::string& base, std::string path, const std::string& name, std::string& file) {
    double least = 0;
    for (;;) {
        const std::string candidate = base + (path == "/" ? "" : path) + "/" + name;
        if (const double v = limitIn(candidate); v > 0 && (least == 0 || v < least)) {
            least = v;
            file = candidate;
        }
        if (path == "/" || path.empty()) return least;
        path = parentOf(path);
    }
}

std::string gib(double bytes) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / kGiB);
    return buf;
}

}  // namespace

double cgroupMemoryLimit(const std::string& selfCgroup, const std::string& root, std::string& file) {
    std::istringstream lines(selfCgroup);
    std::string line;
    double least = 0;
    auto take = [&](double v, const std::string& where) {
        if (v > 0 && (least == 0 || v < least)) {
            least = v;
            file = where;
        }
    };
    while (std::getline(lines, line)) {  // "ID:CONTROLLERS:PATH"
        const size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
        if (b == std::string::npos) continue;
        const std::string controllers = line.substr(a + 1, b - a - 1), path = line.substr(b + 1);
        if (path.empty() || path[0] != '/') continue;
        std::string where;
        if (line.compare(0, a + 1, "0:") == 0 && controllers.empty()) {  // v2: one hierarchy
            const double v = leastUp(root, path, "memory.max", where);
            take(v, where);
        } else if (("," + controllers + ",").find(",memory,") != std::string::npos) {  // v1's memory controller
            const double v = leastUp(root + "/memory", path, "memory.limit_in_bytes", where);
            take(v, where);
        }
    }
    return least;
}

double physicalMemory() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    return pages > 0 && page > 0 ? double(pages) * double(page) : 0;
}

MemoryLimits memoryLimits() {
    MemoryLimits m;
    m.physical = physicalMemory();
    std::ifstream self("/proc/self/cgroup");
    std::ostringstream text;
    text << self.rdbuf();
    m.cgroup = cgroupMemoryLimit(text.str(), "/sys/fs/cgroup", m.cgroupFile);
    rlimit as{};
    if (::getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) m.addressSpace = double(as.rlim_cur);
    std::ifstream statm("/proc/self/statm");  // its first figure: the pages mapped now
    double pages = 0;
    if (statm >> pages) m.mapped = pages * double(::sysconf(_SC_PAGESIZE));
    return m;
}

void refuseIfTooBig(const std::string& flag, double together, double perProcess, const MemoryLimits& limits) {
    const std::string needs = flag + ": needs at least ";
    if (limits.addressSpace > 0 && perProcess + limits.mapped > limits.addressSpace)
        throw SceneError(needs + gib(perProcess) + " of memory in one process, its address-space limit (RLIMIT_AS, ulimit -v) is " +
                         gib(limits.addressSpace) + " (" + std::to_string(int(limits.mapped / (1 << 20))) +
                         " MiB of it in use already)");
    if (limits.cgroup > 0 && together > limits.cgroup && (limits.physical <= 0 || limits.cgroup < limits.physical))
        throw SceneError(needs + gib(together) + " of memory, its cgroup's limit is " + gib(limits.cgroup) + " (" +
                         limits.cgroupFile + ")");
    if (limits.physical > 0 && together > limits.physical)
        throw SceneError(needs + gib(together) + " of memory, this machine has " + gib(limits.physical));
}

void refuseIfTooBig(const std::string& flag, double bytes) { refuseIfTooBig(flag, bytes, bytes, memoryLimits()); }

}  // namespace rt
