// One region of space: an axis-aligned box, only the objects that overlap
// it, and an accelerator over them. This is what one node of the machine
// owns; the reference renderer is the one-region case.
#pragma once
#include <memory>
#include <vector>

#include "accelerator.h"
#include "lattice.h"
#include "ray_job.h"
#include "scene.h"

namespace rt {

class Shader;

// Objects of `all` whose bounds, widened by `margin`, touch `box`. Every
// region of one world uses the same margin (roundingMargin of the world box),
// so that when two adjacent boxes merge, the objects of the merged box are
// exactly the union of theirs (what a boundary slide relies on).
std::vector<Shape> objectsOverlapping(const std::vector<Shape>& all, const Box& box, double margin);
// Same, for one object.
bool overlapsBox(const Shape& s, const Box& box, double margin);

// The objects of a scene binned into the cells of a lattice that covers the
// world (each object in every cell its widened bounds touch), so that the
// objects of a box are looked for among a few cells' instead of the whole
// scene: a 16x16x16 machine builds 4,096 boxes from 66,430 objects. The
// cells that hold a box's faces from inside (binsOf) hold every object
// objectsOverlapping would find; the exact test then keeps those.
class ObjectBins {
public:
    // `all` must outlive the bins.
    ObjectBins(const std::vector<Shape>& all, Lattice cells, double margin);
    // objectsOverlapping(all, box, margin): the same objects in the same
    // (the scene's) order, for a box within the lattice.
    std::vector<Shape> overlapping(const Box& box) const;
    const std::vector<Shape>& all() const { return all_; }

private:
    size_t binOf(int x, int y, int z) const { return (size_t(z) * cells_.cells(1) + y) * cells_.cells(0) + x; }
    void binsOf(const Box& box, Cell& first, Cell& last) const;  // the cells to look in (region.cpp)

    const std::vector<Shape>& all_;
    Lattice cells_;
    double margin_;
    std::vector<std::vector<uint32_t>> bins_;  // indices into all_, ascending
};

class Region {
public:
    Region(const Box& box, std::vector<Shape> objects, AccelKind kind);
    Region(Region&&) = default;

    const Box& box() const { return box_; }
    const std::vector<Shape>& objects() const { return *objects_; }
    const Accelerator& accelerator() const { return *accel_; }

    enum class Step { Terminated, Forward };
    // Traces the job from job.t0 to where it leaves this box (or ends). On a
    // hit it is shaded here (spawning rays and contributions); if it reaches
    // its end it finishes here; otherwise job.t0 becomes the exit parameter
    // and the caller forwards it. job.t0 must be owned by this box.
    Step trace(RayJob& job, const Shader& shader, Mailbox& mailbox, Counters& counters,
               std::vector<RayJob>& spawned, std::vector<Contribution>& out) const {
        return trace(job, boxInterval(job.ray, box_).hi, shader, mailbox, counters, spawned, out);
    }
    // The same, for a caller that has the exit parameter already
    // (tOut == boxInterval(job.ray, box()).hi); `stop`, if given, gets the
    // parameter where the segment ended (the hit, the ray's end or tOut).
    Step trace(RayJob& job, double tOut, const Shader& shader, Mailbox& mailbox, Counters& counters,
               std::vector<RayJob>& spawned, std::vector<Contribution>& out, double* stop = nullptr) const;

private:
    Box box_;
    std::unique_ptr<std::vector<Shape>> objects_;  // stable address for the accelerator
    std::unique_ptr<Accelerator> accel_;
};

}  // namespace rt
