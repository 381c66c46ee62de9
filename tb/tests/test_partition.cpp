// Partition identity: cut the world box into pieces, give each piece its own
// grid over only the objects that overlap it, trace every ray piece by piece
// in the order it crosses them (each piece accepting only hits in its own
// segment of the ray): the image is bit-identical to the unpartitioned one.
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "renderer.h"
#include "scenes.h"

using namespace rt;

namespace {

RenderOptions opts() {
    RenderOptions o;
    o.width = o.height = 64;
    return o;
}

// Cut planes per axis drawn from the scene's own critical coordinates (sphere
// centres, vertices of polygons, so planes along axis-aligned polygons) and
// uniform random ones.
Lattice randomCuts(const Scene& s, uint64_t seed, int perAxis) {
    std::mt19937_64 rng(seed);
    const Box w = s.worldBox();
    std::array<std::vector<double>, 3> planes;
    std::uniform_int_distribution<size_t> pickObj(0, s.objects.size() - 1);
    for (int a = 0; a < 3; ++a) {
        std::set<double> p{w.lo[a], w.hi[a]};
        for (int k = 0; k < perAxis; ++k) {
            const Shape& o = s.objects[pickObj(rng)];
            double c;
            if (const auto* sp = std::get_if<Sphere>(&o.geometry)) c = sp->centre[a];
            else if (const auto* pg = std::get_if<Polygon>(&o.geometry)) c = pg->vertices[rng() % pg->vertices.size()][a];
            else c = std::get<Cone>(o.geometry).base[a];
            if (k % 3 == 2) c = std::uniform_real_distribution<double>(w.lo[a], w.hi[a])(rng);
            if (c > w.lo[a] && c < w.hi[a]) p.insert(c);
        }
        planes[a].assign(p.begin(), p.end());
    }
    return Lattice(planes);
}

void expectIdentity(const Scene& s, const Image& whole, const Partition& part) {
    const RenderResult r = render(s, part, opts());
    EXPECT_TRUE(r.image == whole);
    // Invariant 7: each region holds only objects overlapping its box.
    size_t held = 0;
    for (size_t i = 0; i < part.size(); ++i) {
        const Region& reg = part.region(i);
        held += reg.objects().size();
        for (const Shape& o : reg.objects()) ASSERT_TRUE(o.bounds().expanded(1e-6 * s.worldBox().maxExtent()).overlaps(reg.box()));
    }
    if (part.size() > 1) {
        EXPECT_LT(held / part.size(), s.objects.size());
    }
}

}  // namespace

class PartitionIdentity : public testing::TestWithParam<std::string> {
protected:
    Scene scene() const { return GetParam() == "procedural" ? test::procedural() : test::spd(GetParam()); }
};

TEST_P(PartitionIdentity, UniformSplits) {
    const Scene s = scene();
    const Image whole = render(s, Partition::whole(s), opts()).image;
    for (auto n : {std::array<int, 3>{2, 1, 1}, {1, 2, 1}, {2, 2, 2}, {3, 3, 3}, {4, 4, 4}}) {
        SCOPED_TRACE(testing::Message() << n[0] << "x" << n[1] << "x" << n[2]);
        expectIdentity(s, whole, Partition::uniform(s, n));
    }
}

TEST_P(PartitionIdentity, RandomCutsThroughCentresAndPolygonPlanes) {
    const Scene s = scene();
    const Image whole = render(s, Partition::whole(s), opts()).image;
    for (uint64_t seed = 1; seed <= 4; ++seed) {
        SCOPED_TRACE(testing::Message() << "seed " << seed);
        expectIdentity(s, whole, Partition(s, randomCuts(s, seed, 2 + int(seed)), AccelKind::Grid));
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, PartitionIdentity, testing::Values("balls-3", "rings-2", "gears-2", "procedural"),
                         [](const testing::TestParamInfo<std::string>& i) {
                             std::string n = i.param;
                             n.erase(std::remove(n.begin(), n.end(), '-'), n.end());
                             return n;
                         });

TEST(Partition, CutsExactlyThroughSphereCentresAndTheFloorPlane) {
    // balls-3: every sphere centre of the first level and the floor's plane
    // z = -0.5 become cut planes.
    const Scene s = test::spd("balls-3");
    const Box w = s.worldBox();
    std::array<std::vector<double>, 3> p{{{w.lo.x, 0.0, 0.272166, w.hi.x},
                                          {w.lo.y, -0.371785, 0.0, w.hi.y},
                                          {w.lo.z, -0.5, 0.0, 0.544331, w.hi.z}}};
    const Image whole = render(s, Partition::whole(s), opts()).image;
    expectIdentity(s, whole, Partition(s, Lattice(p), AccelKind::Grid));
}

TEST(Partition, BruteForceRegionsAgreeToo) {
    const Scene s = test::spd("rings-2");
    const Image whole = render(s, Partition::whole(s), opts()).image;
    expectIdentity(s, whole, Partition::uniform(s, {3, 2, 2}, AccelKind::BruteForce));
}

// The bins a machine and a partition find each box's objects with must find
// exactly what scanning the whole scene finds, in the scene's order: boxes
// that do not line up with the bins, boxes that only touch an object's
// widened bounds (closed overlap), flat boxes and the whole world.
TEST(ObjectBins, FindWhatAScanFindsInTheSameOrder) {
    auto boundsOf = [](const std::vector<Shape>& v) {
        std::vector<std::array<double, 6>> b;
        for (const Shape& s : v) {
            const Box x = s.bounds();
            b.push_back({x.lo.x, x.lo.y, x.lo.z, x.hi.x, x.hi.y, x.hi.z});
        }
        return b;
    };
    for (const char* name : {"balls-3", "rings-2", "gears-2"}) {
        const Scene s = test::spd(name);
        const Box w = s.worldBox();
        const double margin = roundingMargin(w);
        std::vector<Box> boxes{w};
        const Lattice other = randomCuts(s, 11, 5);
        for (int z = 0; z < other.cells(2); ++z)
            for (int y = 0; y < other.cells(1); ++y)
                for (int x = 0; x < other.cells(0); ++x) boxes.push_back(other.cellBox({x, y, z}));
        std::mt19937_64 rng(3);
        std::vector<Box> touched;  // widened bounds of 40 objects
        for (int k = 0; k < 40; ++k) touched.push_back(s.objects[rng() % s.objects.size()].bounds().expanded(margin));
        for (int k = 0; k < 40; ++k) {  // faces on those: touching counts
            const Box& o = touched[size_t(k)];
            Box b = w;
            const int a = int(rng() % 3);
            if (k % 4 != 2) b.lo[a] = o.hi[a];
            else b.hi[a] = o.lo[a];
            if (k % 4 < 2) b.hi[a] = b.lo[a];  // flat
            if (b.lo[a] <= b.hi[a]) boxes.push_back(b);
        }
        // Bin planes between those objects' bounds and their widened bounds:
        // only the widened bounds put an object in the bin a touching box
        // lies in.
        std::array<std::vector<double>, 3> tight;
        for (int a = 0; a < 3; ++a) {
            std::set<double> p{w.lo[a], w.hi[a]};
            for (const Box& o : touched) {
                const double c = o.hi[a] - margin / 2;
                if (c > w.lo[a] && c < w.hi[a]) p.insert(c);
            }
            tight[a].assign(p.begin(), p.end());
        }
        for (const Lattice& bins : {Lattice::uniform(w, {1, 1, 1}), Lattice::uniform(w, {4, 3, 5}), randomCuts(s, 5, 4),
                                    Lattice(tight)}) {
            const ObjectBins binned(s.objects, bins, margin);
            // The bins' own cells, and boxes with a face on a bin plane (binsOf
            // looks in the cells inside the faces alone: one bin for a cell).
            std::vector<Box> onPlanes = boxes;
            for (int k = 0; k < 60; ++k) {
                const Cell c{int(rng() % size_t(bins.cells(0))), int(rng() % size_t(bins.cells(1))),
                             int(rng() % size_t(bins.cells(2)))};
                Box b = bins.cellBox(c);
                onPlanes.push_back(b);
                const int a = int(rng() % 3);
                if (k % 3 == 1) b.hi[a] = 0.5 * (b.lo[a] + b.hi[a]);  // the low face on a plane alone
                if (k % 3 == 2) b.hi[a] = b.lo[a];                     // flat, on a plane
                onPlanes.push_back(b);
            }
            for (const Box& b : onPlanes) {
                SCOPED_TRACE(testing::Message() << name << ", box " << b.lo.x << " " << b.lo.y << " " << b.lo.z << " / "
                                                << b.hi.x << " " << b.hi.y << " " << b.hi.z);
                ASSERT_EQ(boundsOf(binned.overlapping(b)), boundsOf(objectsOverlapping(s.objects, b, margin)));
            }
        }
    }
}
