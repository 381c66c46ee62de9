#include "partition.h"

namespace rt {

Partition::Partition(const Scene& scene, const Lattice& cuts, AccelKind kind) : cuts_(cuts), world_(cuts.bounds()) {
    const ObjectBins bins(scene.objects, cuts_, roundingMargin(world_));
    for (int z = 0; z < cuts_.cells(2); ++z)
        for (int y = 0; y < cuts_.cells(1); ++y)
            for (int x = 0; x < cuts_.cells(0); ++x) {
                const Box b = cuts_.cellBox({x, y, z});
                regions_.emplace_back(b, bins.overlapping(b), kind);
            }
}

Partition Partition::whole(const Scene& scene, AccelKind kind) { return uniform(scene, {1, 1, 1}, kind); }

Partition Partition::uniform(const Scene& scene, const std::array<int, 3>& n, AccelKind kind) {
    return Partition(scene, Lattice::uniform(scene.worldBox(), n), kind);
}

}  // namespace rt
