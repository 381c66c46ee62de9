#include "renderer.h"

#include <stdexcept>
#include <string>
#include <thread>

#include "camera.h"
#include "pixel_sum.h"

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

namespace {

int widthOf(const Scene& scene, const RenderOptions& opt) { return opt.width ? opt.width : scene.view.width; }
int heightOf(const Scene& scene, const RenderOptions& opt) { return opt.height ? opt.height : scene.view.height; }

void checkOptions(const Scene& scene, const RenderOptions& opt) {
    if (widthOf(scene, opt) <= 0 || heightOf(scene, opt) <= 0) throw std::invalid_argument("image size must be positive");
    if (opt.maxDepth < 0 || opt.maxDepth > kMaxRayDepth)
        throw std::invalid_argument("max depth must be in [0, " + std::to_string(kMaxRayDepth) + "]");
}

// One pixel's ray tree, traced to its end: its contributions are appended.
void tracePixel(const Camera& camera, const Partition& partition, const Shader& shader, int x, int y, Mailbox& mailbox,
                Counters& counters, std::vector<RayJob>& pending, std::vector<Contribution>& contributions) {
    pending.push_back(primaryJob(camera, x, y, partition.world()));
    ++counters.primaryRays;
    while (!pending.empty()) {
        RayJob job = pending.back();
        pending.pop_back();
        traceThrough(partition, shader, job, mailbox, counters, pending, contributions);
    }
}

}  // namespace

std::vector<Contribution> referenceContributions(const Scene& scene, const RenderOptions& opt) {
    checkOptions(scene, opt);
    const int w = widthOf(scene, opt), h = heightOf(scene, opt);
    const Partition whole = Partition::whole(scene);
    const Camera camera(scene.view, w, h);
    const Shader shader(scene, opt.maxDepth);
    Mailbox mailbox;
    Counters counters;
    std::vector<RayJob> pending;
    std::vector<Contribution> out;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) tracePixel(camera, whole, shader, x, y, mailbox, counters, pending, out);
    return out;
}

RenderResult render(const Scene& scene, const Partition& partition, const RenderOptions& opt) {
    checkOptions(scene, opt);
    const int w = widthOf(scene, opt), h = heightOf(scene, opt);
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
        PixelSums sum(1);
        for (int y = t; y < h; y += threads)
            for (int x = 0; x < w; ++x) {
                contributions.clear();
                tracePixel(camera, partition, shader, x, y, mailbox, counters, pending, contributions);
                sum.clear();
                for (const Contribution& c : contributions) sum.add(0, c);
                result.image.pixels[size_t(y) * w + x] = sum.value(0);
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
