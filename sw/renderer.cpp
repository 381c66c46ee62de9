#include "renderer.h"

#include <stdexcept>
#include <string>
#include <thread>

#include "camera.h"

namespace rt {

void traceThrough(const Partition& partition, const Shader& shader, RayJob job, Mailbox& mailbox,
                  Counters& counters, std::vector<RayJob>& spawned, std::vector<Contribution>& out) {
    for (;;) {
        const std::optional<Cell> cell = partition.cuts().locate(job.ray, job.t0);
        if (!cell || !(job.t0 < job.tEnd)) {  // left the world (or ended exactly on a region face)
            out.push_back(shader.miss(job, counters));
            return;
        }
        if (partition.region(*cell).trace(job, shader, mailbox, counters, spawned, out) == Region::Step::Terminated)
            return;
    }
}

RenderResult render(const Scene& scene, const Partition& partition, const RenderOptions& opt) {
    const int w = opt.width ? opt.width : scene.view.width;
    const int h = opt.height ? opt.height : scene.view.height;
    if (w <= 0 || h <= 0) throw std::invalid_argument("image size must be positive");
    if (opt.maxDepth < 0 || opt.maxDepth > kMaxRayDepth)
        throw std::invalid_argument("max depth must be in [0, " + std::to_string(kMaxRayDepth) + "]");
    const Camera camera(scene.view, w, h);
    const Shader shader(scene, opt.maxDepth);
    RenderResult result{Image(w, h), {}};
    const int threads = std::max(1, std::min(opt.threads, h));
    std::vector<Counters> perThread(threads);

    auto work = [&](int t) {
        Mailbox mailbox;
        Counters& counters = perThread[t];
        std::vector<RayJob> pending;
        std::vector<Contribution> contributions;
        for (int y = t; y < h; y += threads)
            for (int x = 0; x < w; ++x) {
                contributions.clear();
                pending.push_back(primaryJob(camera, x, y, partition.world()));
                ++counters.primaryRays;
                while (!pending.empty()) {
                    RayJob job = pending.back();
                    pending.pop_back();
                    traceThrough(partition, shader, job, mailbox, counters, pending, contributions);
                }
                result.image.pixels[size_t(y) * w + x] = sumInKeyOrder(contributions);
            }
    };
    if (threads == 1) {
        work(0);
    } else {
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t) pool.emplace_back(work, t);
        for (auto& th : pool) th.join();
    }
    for (const Counters& c : perThread) result.counters += c;
    return result;
}

}  // namespace rt
