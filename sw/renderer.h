// The sequential reference renderer: every pixel's ray tree traced region by
// region through a partition (one region by default), each pixel the sum of
// its contributions in fixed point (pixel_sum.h: the same in any order). The
// machine must reproduce its images bit for bit.
#pragma once
#include "counters.h"
#include "image.h"
#include "partition.h"
#include "shading.h"

namespace rt {

struct RenderOptions {
    int width = 0, height = 0;  // 0: the scene's resolution
    int maxDepth = 5;           // mirror/refraction levels below the primary ray
    int threads = 1;            // rows are interleaved over threads; the image does not depend on it
};

struct RenderResult {
    Image image;
    Counters counters;
};

RenderResult render(const Scene& scene, const Partition& partition, const RenderOptions& options);

// Every contribution of the frame, pixel by pixel (row-major), as the
// reference renderer sums them: what a frame buffer must accumulate, each
// exactly once (the tests hold the machine's frame buffer to it).
std::vector<Contribution> referenceContributions(const Scene& scene, const RenderOptions& options);

// Traces one ray job to its end through the partition, region by region, in
// the order it crosses them; spawned rays and contributions are appended.
void traceThrough(const Partition& partition, const Shader& shader, RayJob job, Mailbox& mailbox,
                  Counters& counters, std::vector<RayJob>& spawned, std::vector<Contribution>& out);

}  // namespace rt
