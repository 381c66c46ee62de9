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
