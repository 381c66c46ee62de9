// The reference renderer: the grid finds the same hits as brute force (bit-
// identical images on every SPD scene), contributions are accounted for, and
// threads do not change the image.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include <gtest/gtest.h>

#include "pixel_sum.h"
#include "renderer.h"
#include "scenes.h"
#include "brute_force.h"
#include "grid.h"

using namespace rt;

namespace {

RenderOptions small(int size = 64) {
    RenderOptions o;
    o.width = o.height = size;
    return o;
}

}  // namespace

class GridVsBruteForce : public testing::TestWithParam<std::string> {};

TEST_P(GridVsBruteForce, ImagesAreBitIdentical) {
    const Scene s = test::spd(GetParam());
    const RenderResult grid = render(s, Partition::whole(s, AccelKind::Grid), small());
    const RenderResult brute = render(s, Partition::whole(s, AccelKind::BruteForce), small());
    EXPECT_TRUE(grid.image == brute.image);
    // The same rays were traced and hit the same things...
    EXPECT_EQ(grid.counters.primaryHits, brute.counters.primaryHits);
    EXPECT_EQ(grid.counters.shadowRays, brute.counters.shadowRays);
    EXPECT_EQ(grid.counters.shadowHits, brute.counters.shadowHits);
    EXPECT_EQ(grid.counters.secondaryRays, brute.counters.secondaryRays);
    EXPECT_EQ(grid.counters.secondaryHits, brute.counters.secondaryHits);
    // ...with far fewer intersection tests, except where there is little to skip.
    if (s.objects.size() > 100) {
        EXPECT_LT(grid.counters.intersectionTests() * 5, brute.counters.intersectionTests());
    }
    EXPECT_EQ(brute.counters.voxelSteps, 0u);
    EXPECT_GT(grid.counters.voxelSteps, 0u);
}

INSTANTIATE_TEST_SUITE_P(Spd, GridVsBruteForce,
                         testing::Values("balls-1", "balls-2", "balls-3", "balls-4", "balls-5", "rings-2", "tetra-3",
                                         "gears-2"),
                         [](const testing::TestParamInfo<std::string>& i) {
                             std::string n = i.param;
                             n.erase(std::remove(n.begin(), n.end(), '-'), n.end());
                             return n;
                         });

TEST(Render, ProceduralGridVsBruteForce) {
    const Scene s = test::procedural();
    EXPECT_TRUE(render(s, Partition::whole(s, AccelKind::Grid), small()).image ==
                render(s, Partition::whole(s, AccelKind::BruteForce), small()).image);
}

TEST(Render, ThreadsDoNotChangeTheImage) {
    const Scene s = test::spd("balls-2");
    RenderOptions two = small();
    two.threads = 3;
    const RenderResult a = render(s, Partition::whole(s), small());
    const RenderResult b = render(s, Partition::whole(s), two);
    EXPECT_TRUE(a.image == b.image);
    EXPECT_EQ(a.counters.intersectionTests(), b.counters.intersectionTests());
}

TEST(Render, RayAccounting) {
    // Every ray ends in exactly one way: a hit (shaded or blocked), or an end
    // with a contribution (background, or a shadow ray reaching its light).
    const Scene s = test::spd("gears-2");  // mirrors, refraction, 5 lights
    const RenderResult r = render(s, Partition::whole(s), small(48));
    const Counters& c = r.counters;
    EXPECT_EQ(c.primaryRays, 48u * 48u);
    const uint64_t hits = c.primaryHits + c.shadowHits + c.secondaryHits;
    const uint64_t misses = c.rays() - hits;
    EXPECT_EQ(c.shadings, c.primaryHits + c.secondaryHits);
    // Each shading adds one ambient contribution; each miss one contribution.
    EXPECT_EQ(c.contributions, c.shadings + misses);
    EXPECT_GT(c.secondaryRays, 0u);
    EXPECT_GT(c.shadowHits, 0u);
}

TEST(Render, MaxDepthZeroSpawnsNoSecondaryRays) {
    const Scene s = test::spd("balls-2");
    RenderOptions o = small(32);
    o.maxDepth = 0;
    const RenderResult r = render(s, Partition::whole(s), o);
    EXPECT_EQ(r.counters.secondaryRays, 0u);
    EXPECT_GT(r.counters.shadowRays, 0u);
    RenderOptions deeper = small(32);
    deeper.maxDepth = 3;
    EXPECT_FALSE(render(s, Partition::whole(s), deeper).image == r.image);
}

// The pixel's sum (pixel_sum.h) against sums worked out by hand, in every
// order of arrival.
namespace {
Vec3 sumInOrder(const std::vector<Contribution>& cs) {
    PixelSums s(1);
    for (const Contribution& c : cs) s.add(0, c);
    return s.value(0);
}
// Every permutation gives `expected`, bit for bit.
void expectEveryOrderGives(std::vector<Contribution> cs, const Vec3& expected) {
    std::sort(cs.begin(), cs.end(), [](const Contribution& a, const Contribution& b) { return a.key < b.key; });
    int orders = 0;
    do {
        const Vec3 v = sumInOrder(cs);
        EXPECT_EQ(std::memcmp(&v, &expected, sizeof v), 0) << "order " << orders << ": " << v.x << " " << v.y << " " << v.z;
        ++orders;
    } while (std::next_permutation(cs.begin(), cs.end(),
                                   [](const Contribution& a, const Contribution& b) { return a.key < b.key; }));
    EXPECT_GT(orders, 1);
}
}  // namespace

TEST(PixelSum, IsExactWhereFloatingPointAdditionDependsOnOrder) {
    // In doubles, 1e11 + 0.001 - 1e11 + 0.001 is 0.0020071 (the ulp at 1e11
    // is 1.5e-5); the exact sum is 0.002. Fixed point at 2^-40 rounds each
    // 0.001 once, to round(0.001 * 2^40) = 1099511628 units, and adds exactly.
    const double unit = std::ldexp(1.0, -40);
    const std::vector<Contribution> cs = {
        {0, {0, 0}, Vec3(1e11)}, {0, {0, 1}, Vec3(0.001)}, {0, {1, 0}, Vec3(-1e11)}, {0, {2, 0}, Vec3(0.001)}};
    ASSERT_GT(std::fabs(((1e11 + 0.001) - 1e11) + 0.001 - 0.002), 1e-6);  // the order would matter in doubles
    expectEveryOrderGives(cs, Vec3(2.0 * 1099511628.0 * unit));
    EXPECT_NEAR(sumInOrder(cs).x, 0.002, 1e-12);
}

TEST(PixelSum, RoundsEachComponentOnceToTheNearestUnit) {
    const double unit = std::ldexp(1.0, -40);
    // Half a unit rounds away from zero; less than half vanishes; signs hold.
    expectEveryOrderGives({{0, {0, 0}, Vec3(0.5 * unit, 0.49 * unit, -0.5 * unit)},
                           {0, {1, 0}, Vec3(3.0 * unit, 1.49 * unit, 0.0)}},
                          Vec3(4.0 * unit, 1.0 * unit, -1.0 * unit));
}

TEST(PixelSum, ComponentsOutsideTheRangeAreSummedAsideInKeyOrder) {
    // 1e16 is past 2^40: those two go aside and are summed in key order
    // (-1e16 at path 1 before 1e16 at path 4: 0), the two ones in fixed
    // point (2); an infinite component goes aside too.
    expectEveryOrderGives({{0, {4, 0}, Vec3(1e16)}, {0, {0, 1}, Vec3(1.0)}, {0, {1, 2}, Vec3(-1e16)},
                           {0, {0, 0}, Vec3(1.0)}},
                          Vec3(2.0));
    const double inf = std::numeric_limits<double>::infinity();
    expectEveryOrderGives({{0, {0, 0}, Vec3(inf, 0.0, 0.0)}, {0, {1, 0}, Vec3(1.0)}}, Vec3(inf, 1.0, 1.0));
    // Just below the range it is fixed point, just at it aside.
    const double below = std::nextafter(kFixedRange, 0.0);
    expectEveryOrderGives({{0, {0, 0}, Vec3(below)}, {0, {1, 0}, Vec3(-below)}, {0, {2, 0}, Vec3(0.25)}}, Vec3(0.25));
    FixedRgb f;
    EXPECT_TRUE(toFixed(Vec3(below), f));
    EXPECT_FALSE(toFixed(Vec3(0.0, kFixedRange, 0.0), f));
    EXPECT_FALSE(toFixed(Vec3(0.0, 0.0, std::nan("")), f));
}

TEST(PixelSum, SumsPastSixtyFourBitsStayExact) {
    // A pixel's sum is kept in 64 bits while it fits: below 2^63 units, or
    // 2^23 = 8388608 in colour. Three contributions of 4e6 go past it (in
    // whatever order, the third to arrive would overflow); the exact sum,
    // 12e6 + round(0.001 * 2^40) units, is nearest to the double 12000000.001.
    const Vec3 big(4e6, -4e6, 0.25), small(0.001, -0.001, 0.25);
    expectEveryOrderGives({{0, {0, 0}, big}, {0, {1, 0}, big}, {0, {2, 0}, small}, {0, {3, 0}, big}},
                          Vec3(12000000.001, -12000000.001, 1.0));
    // Past 64 bits and back: the sum is exact whichever part held what.
    expectEveryOrderGives({{0, {0, 0}, big}, {0, {1, 0}, big}, {0, {2, 0}, big}, {0, {3, 0}, -big},
                           {0, {4, 0}, small}},
                          Vec3(8000000.001, -8000000.001, 0.75));
}

TEST(PixelSum, PixelsAreSummedApartAndClearedForTheNext) {
    PixelSums s(3);
    s.add(2, {0, {0, 0}, Vec3(0.5)});
    s.add(0, {0, {0, 0}, Vec3(0.25)});
    s.add(2, {0, {1, 0}, Vec3(1e20)});  // aside, pixel 2 only
    s.add(0, {0, {1, 0}, Vec3(0.25)});
    EXPECT_EQ(s.value(0), Vec3(0.5));
    EXPECT_EQ(s.value(1), Vec3(0.0));
    EXPECT_EQ(s.value(2), Vec3(1e20));
    s.clear();
    for (size_t i = 0; i < 3; ++i) EXPECT_EQ(s.value(i), Vec3(0.0));
}

TEST(Render, BackgroundWhereNothingIsHit) {
    Scene s = test::spd("balls-1");
    s.view.at = s.view.from + (s.view.from - s.view.at);  // look away from the scene, up into the sky
    const RenderResult r = render(s, Partition::whole(s), small(8));
    EXPECT_EQ(r.counters.primaryHits, 0u);
    // The background, rounded to the pixel sum's unit of 2^-40.
    Vec3 expected;
    for (int a = 0; a < 3; ++a) expected[a] = std::round(std::ldexp(s.background[a], 40)) * std::ldexp(1.0, -40);
    EXPECT_NE(expected, s.background);
    EXPECT_LT(std::fabs(expected.x - s.background.x), std::ldexp(1.0, -41));
    for (const Vec3& p : r.image.pixels) EXPECT_EQ(p, expected);
}

TEST(Render, LightingModelByHand) {
    // One sphere seen head-on, one light behind the eye: at the centre pixel
    // N = L = -d = +z, so N.L = R.L = 1, and with one light I = sqrt(1)/2.
    Scene s = parseNff(
        "b 0.1 0.2 0.4\nv\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 10\nhither 1\nresolution 3 3\n"
        "l 0 0 10\nf 1 0.5 0.25 0.6 0.5 10 0 0\ns 0 0 0 1\n",
        "hand.nff");
    const RenderResult r = render(s, Partition::whole(s), RenderOptions{});
    const Vec3 C(1, 0.5, 0.25);
    const double I = 0.5, kd = 0.6, ks = 0.5;
    const Vec3 ambient = C * kd * I, diffuse = I * kd * 1.0 * C, highlight = Vec3(I * ks * 1.0);
    const Vec3 mirror = ks * Vec3(0.1, 0.2, 0.4);  // the mirror ray leaves the world: background
    const Vec3 expect = ambient + diffuse + highlight + mirror;
    const Vec3 got = r.image.pixels[4];
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expect[c], 1e-12);
    EXPECT_EQ(r.counters.primaryHits, 9u);  // 10 degrees: every pixel sees the sphere
    EXPECT_EQ(r.counters.shadowHits, 0u);
}

TEST(Render, TransparentSphereRefracts) {
    // A glass sphere in front of a red wall: the centre ray passes straight
    // through (normal incidence), so the pixel carries T x the wall's colour.
    Scene s = parseNff(
        "b 0 0 0\nv\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 10\nhither 1\nresolution 3 3\n"
        "l 0 0 10\nf 1 1 1 0 0 0 0.5 1.5\ns 0 0 0 1\n"
        "f 1 0 0 1 0 0 0 0\np 4\n-10 -10 -3\n10 -10 -3\n10 10 -3\n-10 10 -3\n",
        "glass.nff");
    const RenderResult r = render(s, Partition::whole(s), RenderOptions{});
    // Wall: ambient 0.5 + diffuse 0.5 with N.L = 1 (the light shines through
    // nothing: shadow rays are blocked by the glass), so only ambient: 0.5.
    // Through two surfaces: weight 0.5 * 0.5.
    EXPECT_NEAR(r.image.pixels[4].x, 0.25 * 0.5, 1e-12);
    EXPECT_EQ(r.image.pixels[4].y, 0.0);
    EXPECT_GT(r.counters.secondaryHits, 0u);
}

// ---- A grid spans the part of its box its objects occupy (grid.h) ----

namespace {
Shape ball(double x, double y, double z, double r, uint32_t id) {
    Shape s;
    s.geometry = Sphere{Vec3(x, y, z), r, false};
    s.id = id;
    return s;
}
}  // namespace

TEST(GridOverOccupiedPart, AThickBoxWithTwoSpheresAtOneEndTestsThemOnlyNearThem) {
    // A machine's box past a cluster's edge: 0.9 long, two spheres at its
    // near end. Over the whole box the grid would be 9 x 1 x 1 (cells
    // 0.1 x 0.13 x 0.13), and every ray through the first cell would test
    // both spheres; over their part it is finer across, and a ray that
    // passes beside them, or through the rest of the box, tests nothing.
    const Box box{Vec3(0.1, 0, 0), Vec3(1.0, 0.13, 0.13)};
    const std::vector<Shape> objects{ball(0.12, 0.065, 0.065, 0.02, 0), ball(0.15, 0.065, 0.065, 0.02, 1)};
    EXPECT_EQ(UniformGrid::resolution(box, 2), (std::array<int, 3>{9, 1, 1}));
    const UniformGrid g(objects, box);
    const Box part = UniformGrid::occupiedPart(objects, box);
    EXPECT_LE(part.hi.x, 0.2 + 1e-9);  // one cell of the whole box's grid, about the spheres
    EXPECT_GE(part.lo.x, 0.1);
    EXPECT_GT(g.lattice().cells(1), 1);  // finer across than the whole box's one cell
    const BruteForce all(objects);
    Mailbox mb;
    auto traced = [&](const Accelerator& a, const Ray& r, Counters& c) { return a.closestHit(r, 0, 10, mb, c); };
    // Beside the spheres, in their cell of the whole box's grid: no test.
    Counters beside;
    EXPECT_FALSE(traced(g, Ray(Vec3(0.13, -1, 0.01), Vec3(0, 1, 0)), beside).valid());
    EXPECT_EQ(beside.tests[size_t(PrimitiveKind::Sphere)], 0u);
    // Through the rest of the box: no cell walked.
    Counters far;
    EXPECT_FALSE(traced(g, Ray(Vec3(0.6, -1, 0.065), Vec3(0, 1, 0)), far).valid());
    EXPECT_EQ(far.voxelSteps, 0u);
    // The hits are brute force's, to the bit, over a fan of rays.
    for (int i = 0; i <= 200; ++i) {
        const double a = -0.5 + i * 0.005;
        const Ray r(Vec3(0.13, -1, 0.065), glm::normalize(Vec3(std::sin(a) * 0.1, 1, std::cos(a) * 0.02)));
        Counters c1, c2;
        const Hit h = traced(g, r, c1), b = traced(all, r, c2);
        EXPECT_EQ(h.t, b.t) << i;
        EXPECT_EQ(h.object, b.object) << i;
    }
}

TEST(GridOverOccupiedPart, AFloorAloneGetsAFewCellsNotAFlatSheetOfThem) {
    // A polygon has no thickness: its part is one cell of the whole box's
    // grid thick, so its volume, and the cells it gets, stay those of a box.
    Shape floor;
    Polygon p;
    p.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    ASSERT_TRUE(p.finish());
    floor.geometry = p;
    const Box box{Vec3(0), Vec3(1)};
    const std::vector<Shape> objects{floor};  // (the grid keeps a reference)
    const UniformGrid g(objects, box);
    for (int a = 0; a < 3; ++a) EXPECT_LE(g.lattice().cells(a), 3) << a;
    Mailbox mb;
    Counters c;
    const Hit h = g.closestHit(Ray(Vec3(0.5, 0.5, 1), Vec3(0, 0, -1)), 0, 10, mb, c);
    EXPECT_TRUE(h.valid());
    EXPECT_EQ(h.t, 1.0);
}

TEST(GridOverOccupiedPart, ABoxWithNoObjectsWalksNoCell) {
    // A node that only passes rays on: its tracer finds no hit and does no
    // voxel steps, the cost a machine's node there would not pay.
    const std::vector<Shape> none;
    const UniformGrid g(none, Box{Vec3(0), Vec3(1)});
    Mailbox mb;
    Counters c;
    EXPECT_FALSE(g.closestHit(Ray(Vec3(0.5, -1, 0.5), Vec3(0, 1, 0)), 0, 10, mb, c).valid());
    EXPECT_EQ(c.voxelSteps, 0u);
}
