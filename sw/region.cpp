#include "region.h"

#include "shading.h"

namespace rt {

bool overlapsBox(const Shape& s, const Box& box, double margin) { return s.bounds().expanded(margin).overlaps(box); }

std::vector<Shape> objectsOverlapping(const std::vector<Shape>& all, const Box& box, double margin) {
    std::vector<Shape> out;
    for (const Shape& s : all)
        if (overlapsBox(s, box, margin)) out.push_back(s);
    return out;
}

Region::Region(const Box& box, std::vector<Shape> objects, AccelKind kind)
    : box_(box), objects_(std::make_unique<std::vector<Shape>>(std::move(objects))) {
    accel_ = makeAccelerator(kind, *objects_, box_);
}

Region::Step Region::trace(RayJob& job, const Shader& shader, Mailbox& mailbox, Counters& counters,
                           std::vector<RayJob>& spawned, std::vector<Contribution>& out) const {
    const double tOut = boxInterval(job.ray, box_).hi;
    const double end = std::min(tOut, job.tEnd);
    const Hit hit = accel_->closestHit(job.ray, job.t0, end, mailbox, counters);
    if (hit.valid()) {
        shader.hit(job, hit.t, (*objects_)[hit.object], counters, spawned, out);
        return Step::Terminated;
    }
    if (job.tEnd <= tOut) {  // a shadow ray that reached its light inside this box
        out.push_back(shader.miss(job, counters));
        return Step::Terminated;
    }
    job.t0 = tOut;
    return Step::Forward;
}

}  // namespace rt
