// A job too big for this machine is refused before it starts, with the
// estimate, rather than dying of std::bad_alloc half way with a message that
// names nothing (--size 65536x65536 did).
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
// on 16x16x16 and 24x24x24: 52.7 and 52.3 KB): its module and process
// stacks, its six links, its ports to every frame-buffer unit. A 32x32x32
// mesh needs about 1.7 GiB before its scene and image.
constexpr double kRtsimBytesPerNode = 53 * 1024;

// The machine's physical memory in bytes (0 if unknown).
double physicalMemory();

// Throws SceneError ("FLAG: needs about X GiB, this machine has Y GiB") if
// `bytes` is more than the machine's physical memory.
void refuseIfTooBig(const std::string& flag, double bytes);

}  // namespace rt
