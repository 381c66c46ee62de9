// Uniform grid over one region's box, traversed with the 3D-DDA of
// Amanatides & Woo (Lattice::walk), with mailboxing.
//
// The grid spans the part of the box its objects occupy (occupiedPart): a
// ray through the rest walks no cell and tests nothing, and a ray through a
// box with no objects walks none at all. Resolution rule, over
// that part: about kCellsPerObject cells per object, cubical as far as the
// part allows: with n objects in a part of volume V, k = cbrt(lambda n / V)
// cells per unit length and n_a = clamp(round(extent_a k), 1, kMaxCellsPerAxis)
// along each axis. lambda = 8, measured (doc/rendering.md, "Grid resolution").
#pragma once
#include "accelerator.h"
#include "lattice.h"

namespace rt {

class UniformGrid final : public Accelerator {
public:
    static constexpr double kCellsPerObject = 8.0;
    static constexpr int kMaxCellsPerAxis = 256;
    static std::array<int, 3> resolution(const Box& box, size_t objects);
    // The part of `box` its objects' bounds (widened by the rounding margin)
    // cover, at least one cell of the whole box's grid thick along each
    // axis; the box itself if it holds none. A thick box with a few objects
    // at one end (a machine's box past a cluster's edge) gets a fine grid
    // over them, not a few coarse cells each of which every passing ray
    // tests them all in (doc/rendering.md, "Grid resolution").
    static Box occupiedPart(const std::vector<Shape>& objects, const Box& box);
    // A grid's size, counted without building it: its cells and references
    // (an object listed in a cell), and the bytes it takes at its peak
    // while being built. Objects that overlap much make references grow as
    // their count squared: start-up refuses a machine that would not fit
    // (models/machine/binning_memory.h).
    struct Size {
        uint64_t cells = 0, references = 0;
        double bytes(size_t objects) const;
    };
    static Size sizeFor(const std::vector<Shape>& objects, const Box& box);
    // The most references a grid holds (its offsets are 32-bit).
    static constexpr uint64_t kMaxReferences = 0xffffffffu;

    UniformGrid(const std::vector<Shape>& objects, const Box& box);
    Hit closestHit(const Ray& r, double t0, double t1, Mailbox& mailbox, Counters& counters) const override;
    std::string describe() const override;
    const Lattice& lattice() const { return lattice_; }
    const Lattice* grid() const override { return &lattice_; }
    // Objects listed in cell c (for tests).
    std::vector<uint32_t> cellObjects(const Cell& c) const;

private:
    UniformGrid(const std::vector<Shape>& objects, const Box& box, const Box& part);
    long cellIndex(const Cell& c) const { return (long(c[2]) * lattice_.cells(1) + c[1]) * lattice_.cells(0) + c[0]; }
    const std::vector<Shape>& objects_;
    Lattice lattice_;
    std::vector<uint32_t> start_;  // CSR: cell i lists items_[start_[i] .. start_[i+1])
    std::vector<uint32_t> items_;
};

}  // namespace rt
