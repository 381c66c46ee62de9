// The world box cut by planes into regions, each with only the objects that
// overlap it. A 1x1x1 partition is the reference renderer's; others test the
// partition identity and stand in for the machine's static splits.
#pragma once
#include <vector>

#include "lattice.h"
#include "region.h"

namespace rt {

class Partition {
public:
    // One region per cell of `cuts`; the outer planes of `cuts` are the world box.
    Partition(const Scene& scene, const Lattice& cuts, AccelKind kind);
    // The whole world box as one region.
    static Partition whole(const Scene& scene, AccelKind kind = AccelKind::Grid);
    // n[a] equal slices per axis of the world box.
    static Partition uniform(const Scene& scene, const std::array<int, 3>& n, AccelKind kind = AccelKind::Grid);

    const Lattice& cuts() const { return cuts_; }
    const Box& world() const { return world_; }
    size_t size() const { return regions_.size(); }
    const Region& region(const Cell& c) const { return regions_[index(c)]; }
    const Region& region(size_t i) const { return regions_[i]; }

private:
    size_t index(const Cell& c) const { return (size_t(c[2]) * cuts_.cells(1) + c[1]) * cuts_.cells(0) + c[0]; }
    Lattice cuts_;
    Box world_;
    std::vector<Region> regions_;
};

}  // namespace rt
