#include "machine/binning_memory.h"

#include <algorithm>

#include "grid.h"
#include "balance/initial_split.h"
#include "base/mesh_geometry.h"

namespace rt {

BinningSize binningSize(const Scene& scene, const MachineConfig& cfg) {
    const Box world = scene.worldBox();
    const Lattice cuts = Lattice::uniform(world, cfg.dims);
    const ColumnGeometry columns(cfg.balance.axis, cfg.dims);
    const ObjectBins bins(scene.objects, cuts, roundingMargin(world));
    // (without the camera: a start that weighs the primary rays' entries is estimated without them)
    const ColumnPlanes planes = initialPlanes(cfg, cuts, world, bins, minThicknessOf(cfg, world));
    BinningSize s;
    for (size_t i = 0; i < size_t(cfg.nodeCount()); ++i) {
        const Box b = nodeBox(cellAt(i, cfg.dims), cuts, columns, planes);
        const std::vector<Shape> objects = bins.overlapping(b);
        const UniformGrid::Size g = UniformGrid::sizeFor(objects, b);
        s.bytes += g.bytes(objects.size()) + double(objects.size()) * sizeof(Shape);
        s.largestGrid = std::max(s.largestGrid, double(g.references));
    }
    return s;
}

}  // namespace rt
