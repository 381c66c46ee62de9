// A job too big for this machine is refused before it starts, with the
// estimate, rather than dying of std::bad_alloc half way with a message that
// names nothing (--size 65536x65536 did). "This machine" is what the
// process may use: the least of the physical memory, its cgroup's memory
// limit and its address-space limit (RLIMIT_AS, `ulimit -v`); under
// `ulimit -v 8000000` a 14 GiB job started on a 23 GiB machine and ended in
// std::bad_alloc.
#pragma once
#include <string>

namespace rt {

// Bytes per image pixel, measured (peak resident memory against image size
// on a sparse scene, --spheres 10 at 256x256 and 2048x2048): rtref about 27,
// rtsim about 103 (every node's pixel list, the frame buffer's pixel sums,
// the contributions queued on its ports, the image). A lower bound: a
// scene's rays in flight add to it.
constexpr double kRtrefBytesPerPixel = 27;
constexpr double kRtsimBytesPerPixel = 103;
// Bytes per node of rtsim's mesh, measured the same way (--spheres 1 at 8x8
// on 24x24x24 and 32x32x32: 30.9 and 28.9 KB): its module, its six links,
// its ports to every frame-buffer unit (a link that carries no message
// holds no lanes: channel/link.h). A 32x32x32 mesh needs about 1 GiB
// before its scene and image.
constexpr double kRtsimBytesPerNode = 31 * 1024;

// The limits a job's memory runs into, in bytes (0: none, or unknown).
struct MemoryLimits {
    double physical = 0;      // the machine's physical memory: all the job's processes together
    double cgroup = 0;        // the cgroup's memory limit: likewise
    std::string cgroupFile;   // where it was read
    double addressSpace = 0;  // RLIMIT_AS's soft limit: each process on its own (children inherit it)
    double mapped = 0;        // of it, what this process has mapped already
};

// This process's limits: sysconf, getrlimit(RLIMIT_AS), /proc/self/statm and
// the cgroup's limit (cgroupMemoryLimit of /proc/self/cgroup, /sys/fs/cgroup).
MemoryLimits memoryLimits();

// The memory limit of the cgroup that `selfCgroup` (the text of
// /proc/self/cgroup) names, under the cgroup file system mounted at `root`:
// v2's memory.max, v1's memory/.../memory.limit_in_bytes, the least of the
// cgroup's and its parents' that exist (a container sees its own cgroup as
// the root). "max", or v1's unlimited (about 2^63): none. Returns 0 if
// none, and sets `file` to the file that held the limit.
double cgroupMemoryLimit(const std::string& selfCgroup, const std::string& root, std::string& file);

// The machine's physical memory in bytes (0 if unknown).
double physicalMemory();

// Throws SceneError ("FLAG: needs at least X GiB of memory, LIMIT") if the
// job does not fit `limits`: `together`, the bytes of all its processes at
// once, against the physical memory and the cgroup's limit; `perProcess`,
// its largest process's, against the address-space limit.
void refuseIfTooBig(const std::string& flag, double together, double perProcess, const MemoryLimits& limits);
// One process's `bytes`, against this process's limits.
void refuseIfTooBig(const std::string& flag, double bytes);

}  // namespace rt
