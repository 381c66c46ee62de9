#include "region.h"

#include <algorithm>

#include "shading.h"

namespace rt {

bool overlapsBox(const Shape& s, const Box& box, double margin) { return s.bounds().expanded(margin).overlaps(box); }

std::vector<Shape> objectsOverlapping(const std::vector<Shape>& all, const Box& box, double margin) {
    std::vector<Shape> out;
    for (const Shape& s : all)
        if (overlapsBox(s, box, margin)) out.push_back(s);
    return out;
}

ObjectBins::ObjectBins(const std::vector<Shape>& all, Lattice cells, double margin)
    : all_(all), cells_(std::move(cells)), margin_(margin), bins_(size_t(cells_.cellCount())) {
    for (size_t i = 0; i < all_.size(); ++i) {
        Cell first, last;
        cells_.overlapRange(all_[i].bounds().expanded(margin_), first, last);
        for (int z = first[2]; z <= last[2]; ++z)
            for (int y = first[1]; y <= last[1]; ++y)
                for (int x = first[0]; x <= last[0]; ++x) bins_[binOf(x, y, z)].push_back(uint32_t(i));
    }
}

// On each axis, from the cell that holds the box's low face from inside (at
// a plane, the cell above it) to the cell that holds its high face (at a
// plane, the cell below). An object is binned into every cell its widened
// bounds E touch, closed, and it is the box's iff E touches the box
// (overlapsBox); E.hi >= box.lo and E.lo <= box.hi put E's cells and these
// on each axis in one run (the searches are monotone), so one of these
// holds it. The closed range (overlapRange) takes in the cells beyond each
// face too: a box that is one cell of the lattice looked in 27 bins and
// sorted what it found (doc/history.md, "At 32x32x32"); here it looks in
// one, already in order. A flat axis keeps the closed range.
void ObjectBins::binsOf(const Box& box, Cell& first, Cell& last) const {
    cells_.overlapRange(box, first, last);
    for (int a = 0; a < 3; ++a) {
        const std::vector<double>& p = cells_.planes(a);
        const int n = cells_.cells(a);
        const int f = std::clamp(int(std::upper_bound(p.begin(), p.end(), box.lo[a]) - p.begin()) - 1, 0, n - 1);
        const int l = std::clamp(int(std::lower_bound(p.begin(), p.end(), box.hi[a]) - p.begin()) - 1, 0, n - 1);
        if (f <= l) {
            first[a] = f;
            last[a] = l;
        }
    }
}

std::vector<Shape> ObjectBins::overlapping(const Box& box) const {
    Cell first, last;
    binsOf(box, first, last);
    std::vector<uint32_t> candidates;
    for (int z = first[2]; z <= last[2]; ++z)
        for (int y = first[1]; y <= last[1]; ++y)
            for (int x = first[0]; x <= last[0]; ++x) {
                const std::vector<uint32_t>& b = bins_[binOf(x, y, z)];
                candidates.insert(candidates.end(), b.begin(), b.end());
            }
    if (first != last) {  // (one bin is in order, each object in it once)
        std::sort(candidates.begin(), candidates.end());
        candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    }
    std::vector<Shape> out;
    for (uint32_t i : candidates)
        if (overlapsBox(all_[i], box, margin_)) out.push_back(all_[i]);
    return out;
}

Region::Region(const Box& box, std::vector<Shape> objects, AccelKind kind)
    : box_(box), objects_(std::make_unique<std::vector<Shape>>(std::move(objects))) {
    accel_ = makeAccelerator(kind, *objects_, box_);
}

Region::Step Region::trace(RayJob& job, double tOut, const Shader& shader, Mailbox& mailbox, Counters& counters,
                           std::vector<RayJob>& spawned, std::vector<Contribution>& out, double* stop) const {
    const double end = std::min(tOut, job.tEnd);
    const Hit hit = accel_->closestHit(job.ray, job.t0, end, mailbox, counters);
    if (stop) *stop = hit.valid() ? hit.t : end;
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
