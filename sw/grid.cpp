#include "grid.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "brute_force.h"

namespace rt {

std::array<int, 3> UniformGrid::resolution(const Box& box, size_t objects) {
    const Vec3 e = box.extent();
    const double volume = e.x * e.y * e.z;
    const double k = std::cbrt(kCellsPerObject * double(std::max<size_t>(objects, 1)) / volume);
    std::array<int, 3> n{};
    for (int a = 0; a < 3; ++a) n[a] = int(std::clamp(std::lround(e[a] * k), 1L, long(kMaxCellsPerAxis)));
    return n;
}

Box UniformGrid::occupiedPart(const std::vector<Shape>& objects, const Box& box) {
    if (objects.empty()) return box;
    const double margin = roundingMargin(box);
    Box o;
    for (const Shape& s : objects) o.add(s.bounds().expanded(margin));
    const std::array<int, 3> whole = resolution(box, objects.size());
    Box part = box;
    for (int a = 0; a < 3; ++a) {
        // At least one cell of the whole box's grid thick (a floor polygon
        // alone would otherwise make a flat part, of volume near 0, and a
        // grid of 256 x 256 cells).
        const double cell = (box.hi[a] - box.lo[a]) / whole[size_t(a)];
        double lo = std::max(box.lo[a], o.lo[a]), hi = std::min(box.hi[a], o.hi[a]);
        if (hi - lo < cell) {
            lo = std::clamp(0.5 * (lo + hi) - 0.5 * cell, box.lo[a], box.hi[a] - cell);
            hi = lo + cell;
        }
        part.lo[a] = lo;
        part.hi[a] = hi;
    }
    return part;
}

UniformGrid::Size UniformGrid::sizeFor(const std::vector<Shape>& objects, const Box& box) {
    const Box part = occupiedPart(objects, box);
    const Lattice lattice = Lattice::uniform(part, resolution(part, objects.size()));
    const double margin = roundingMargin(box);
    Size s;
    s.cells = uint64_t(lattice.cellCount());
    for (const Shape& o : objects) {
        Cell f, l;
        lattice.overlapRange(o.bounds().expanded(margin), f, l);
        s.references += uint64_t(l[0] - f[0] + 1) * uint64_t(l[1] - f[1] + 1) * uint64_t(l[2] - f[2] + 1);
    }
    return s;
}

double UniformGrid::Size::bytes(size_t objects) const {
    // The references and the offsets; while building, the counts and each
    // object's cell range besides.
    return 4.0 * double(references) + 8.0 * double(cells + 1) + 24.0 * double(objects);
}

UniformGrid::UniformGrid(const std::vector<Shape>& objects, const Box& box) : UniformGrid(objects, box, occupiedPart(objects, box)) {}

UniformGrid::UniformGrid(const std::vector<Shape>& objects, const Box& box, const Box& part)
    : objects_(objects), lattice_(Lattice::uniform(part, resolution(part, objects.size()))) {
    // Objects go into every cell their bounds touch, widened by a margin far
    // above rounding error, so a hit point that rounding puts just across a
    // cell face is still found in the cell the DDA is in.
    const double margin = roundingMargin(box);
    const long cells = lattice_.cellCount();
    std::vector<uint32_t> count(cells + 1, 0);
    std::vector<std::pair<Cell, Cell>> ranges(objects.size());
    for (size_t i = 0; i < objects.size(); ++i) {
        Cell f, l;
        lattice_.overlapRange(objects[i].bounds().expanded(margin), f, l);
        ranges[i] = {f, l};
        for (int z = f[2]; z <= l[2]; ++z)
            for (int y = f[1]; y <= l[1]; ++y)
                for (int x = f[0]; x <= l[0]; ++x) ++count[cellIndex({x, y, z}) + 1];
    }
    uint64_t references = 0;
    for (long c = 0; c < cells; ++c) references += count[c + 1];
    if (references > kMaxReferences)  // (32-bit offsets would wrap: a wrong grid, not a slow one)
        throw std::length_error("a grid of " + std::to_string(references) + " references (objects listed in cells): more than " +
                                std::to_string(kMaxReferences));
    start_.assign(cells + 1, 0);
    for (long c = 0; c < cells; ++c) start_[c + 1] = start_[c] + count[c + 1];
    items_.resize(start_[cells]);
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < objects.size(); ++i) {
        const auto& [f, l] = ranges[i];
        for (int z = f[2]; z <= l[2]; ++z)
            for (int y = f[1]; y <= l[1]; ++y)
                for (int x = f[0]; x <= l[0]; ++x) items_[fill[cellIndex({x, y, z})]++] = uint32_t(i);
    }
}

Hit UniformGrid::closestHit(const Ray& r, double t0, double t1, Mailbox& mailbox, Counters& counters) const {
    Hit best;
    if (objects_.empty()) return best;  // nothing occupies the box: no cell to walk
    mailbox.begin(objects_.size());
    lattice_.walk(r, t0, t1, [&](const Cell& c, const Interval& seg) {
        ++counters.voxelSteps;
        const long ci = cellIndex(c);
        for (uint32_t k = start_[ci]; k < start_[ci + 1]; ++k) {
            const uint32_t obj = items_[k];
            if (mailbox.firstVisit(obj)) testObject(objects_, obj, r, t0, t1, best, counters);
        }
        // A hit before this cell's exit cannot be beaten by objects further
        // on; a hit exactly at the exit could tie with one in the next cell.
        return !(best.t < seg.hi);
    });
    return best;
}

std::string UniformGrid::describe() const {
    std::ostringstream s;
    s << "grid " << lattice_.cells(0) << "x" << lattice_.cells(1) << "x" << lattice_.cells(2) << ", "
      << items_.size() << " references";
    return s.str();
}

std::vector<uint32_t> UniformGrid::cellObjects(const Cell& c) const {
    const long ci = cellIndex(c);
    return std::vector<uint32_t>(items_.begin() + start_[ci], items_.begin() + start_[ci + 1]);
}

std::unique_ptr<Accelerator> makeAccelerator(AccelKind kind, const std::vector<Shape>& objects, const Box& box) {
    if (kind == AccelKind::BruteForce) return std::make_unique<BruteForce>(objects);
    return std::make_unique<UniformGrid>(objects, box);
}

}  // namespace rt
