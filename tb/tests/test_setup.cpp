// Where a frame starts, without a machine: the columns' initial planes,
// the nodes' boxes, which node generates each primary ray, the host's
// credit shared out exactly; and between frames, the boundaries read back
// from a report and resplit's choice of the next frame's, on reports
// written here with values worked out by hand.
#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "frame_state_json.h"
#include "balance/between_frames.h"
#include "balance/initial_split.h"
#include "balance/sample_end.h"
#include "procedural.h"
#include "shading.h"

using namespace rt;

namespace {

Shape sphere(Vec3 c, double r, uint32_t id) { return Shape{Sphere{c, r, false}, 0, id}; }

MachineConfig mesh(std::array<int, 3> dims, int axis = 0) {
    MachineConfig m;
    m.dims = dims;
    m.balance.axis = axis;
    return m;
}

// `--start-mix auto` and `--sample-end auto` weigh the scene's test against
// a ray's hop: `sample` on a column of four of the default machine, two
// spheres, and the machine with a sphere test of `test`.
MachineConfig sampleColumn() {
    MachineConfig m = mesh({4, 1, 1});
    m.balance.policy = "sample";
    return m;
}
const std::vector<Shape> kTwoSpheres{sphere(Vec3(0.5), 0.1, 0), sphere(Vec3(0.2), 0.1, 1)};
// The objects seen along x from `eyeX`, looking at the middle of the unit cube.
Scene viewedAlongX(const std::vector<Shape>& objects, double eyeX) {
    Scene s;
    s.objects = objects;
    s.declaredBounds = Box{Vec3(0.0), Vec3(1.0)};
    s.view.from = Vec3(eyeX, 0.5, 0.5);
    s.view.at = Vec3(0.5);
    s.view.up = Vec3(0, 0, 1);
    s.view.width = s.view.height = 16;
    return s;
}
MachineConfig withSphereTest(MachineConfig c, Picos test) {
    c.costs.test[0] = test;
    return c;
}

}  // namespace

// ---- The initial split (initial_split.h) ----

TEST(InitialSplit, UniformUnlessStartedElsewhereOrAtTheMedians) {
    const Box world{Vec3(0.0), Vec3(1.0)};
    MachineConfig m = mesh({2, 2, 1});
    const Lattice cuts = Lattice::uniform(world, m.dims);
    // Column y = 0: centres at x = .05 .1 .15 .2; column y = 1: none.
    std::vector<Shape> objects;
    for (int i = 0; i < 4; ++i) objects.push_back(sphere(Vec3(0.05 * (i + 1), 0.25, 0.5), 0.01, uint32_t(i)));
    const ObjectBins bins(objects, cuts, 1e-9);
    const ColumnPlanes uniform = initialPlanes(m, cuts, world, bins, 0.025);
    ASSERT_EQ(uniform.size(), 2u);
    for (const auto& p : uniform) EXPECT_EQ(p, cuts.planes(0));

    m.balance.policy = "median";
    const ColumnPlanes median = initialPlanes(m, cuts, world, bins, 0.025);
    ASSERT_EQ(median[0].size(), 3u);
    EXPECT_DOUBLE_EQ(median[0][1], 0.15);  // the 2/4th centre
    EXPECT_EQ(median[0].front(), 0.0);
    EXPECT_EQ(median[0].back(), 1.0);
    EXPECT_EQ(median[1], cuts.planes(0));                         // no objects: uniform

    // Mixed with the column's length (--start-mix): the plane where
    // mix x (objects at or below it) / 4 + (1 - mix) x its share of [0, 1] passes 1/2.
    for (const auto& [mix, plane] : {std::pair{0.5, 0.2},  // 0.5 x 3/4 + 0.5 x 0.2 < 1/2 just below 0.2; 0.6 at it
                                     std::pair{0.2, 0.375},  // past every centre: 0.2 + 0.8 x = 1/2
                                     std::pair{0.0, 0.5}}) {  // the length alone: uniform
        m.balance.startMix = mix;
        const ColumnPlanes mixed = initialPlanes(m, cuts, world, bins, 0.025);
        EXPECT_NEAR(mixed[0][1], plane, 1e-12) << "start mix " << mix;
        EXPECT_EQ(mixed[1], cuts.planes(0)) << "start mix " << mix;  // no objects: uniform at any mix
    }
    m.balance.startMix = 1;

    m.startBoundaries = {{0.3}, {0.8}};
    const ColumnPlanes started = initialPlanes(m, cuts, world, bins, 0.025);
    EXPECT_EQ(started[0], (std::vector<double>{0.0, 0.3, 1.0}));
    EXPECT_EQ(started[1], (std::vector<double>{0.0, 0.8, 1.0}));
    EXPECT_EQ(nodeBox(Cell{1, 1, 0}, cuts, ColumnGeometry(0, m.dims), started).lo.x, 0.8);
    m.startBoundaries = {{0.99}, {0.5}};  // a box thinner than the minimum
    EXPECT_THROW(initialPlanes(m, cuts, world, bins, 0.025), std::invalid_argument);
    m.startBoundaries = {{0.5}};  // one column short
    EXPECT_THROW(initialPlanes(m, cuts, world, bins, 0.025), std::invalid_argument);
}

// Auto's half start keeps a column's planes uniform where it leaves the
// column's heaviest box (by object centres) as heavy as the uniform split's:
// it would only lengthen boxes (tetra-3 at N = 5 to 7 lost up to 53 % so);
// and, where every column starts at the same planes (aligned: all the
// objects counted), where it lightens it by no more than chance, 2
// standard deviations of an even spread's box (the square root of the
// uniform split's count): Fig. 4's spheres spread evenly lost so (1.037 at
// N = 8, f = 1). By hand, a column of two over [0, 1] at start mix 0.5:
// centres .05 to .2 put the plane just past .2 (as above), and box 0 still
// holds all four; centres .05 to .4 put it just past .3 (0.5 x 6/8 + 0.5 x
// 0.3 passes 1/2), and box 0 holds 6 of 8 where the uniform split's held 8:
// lighter by 2, under 2 sqrt(8) = 5.66. 100 centres .004 to .4 put it at
// 2/7 (0.5 x x / 0.4 + 0.5 x passes 1/2 there), box 0 holding 71 of 100:
// lighter by 29, over 2 sqrt(100) = 20.
TEST(InitialSplit, TheHalfStartOnlyWhereItLightensTheHeaviestBox) {
    const Box world{Vec3(0.0), Vec3(1.0)};
    MachineConfig m = mesh({2, 1, 1});
    m.balance.policy = "sample";
    m.balance.startMix = 0.5;
    const Lattice cuts = Lattice::uniform(world, m.dims);
    const auto planeWith = [&](int objects, bool lighterOnly, bool aligned, double apart = 0.05) {
        std::vector<Shape> s;
        for (int i = 0; i < objects; ++i) s.push_back(sphere(Vec3(apart * (i + 1), 0.5, 0.5), 0.001, uint32_t(i)));
        const ObjectBins bins(s, cuts, 1e-9);
        m.balance.startLighterOnly = lighterOnly;
        m.balance.startAligned = aligned;
        return initialPlanes(m, cuts, world, bins, 0.025)[0][1];
    };
    for (bool aligned : {false, true}) {
        SCOPED_TRACE(aligned ? "aligned" : "each column its own");
        EXPECT_NEAR(planeWith(4, false, aligned), 0.2, 1e-12);
        EXPECT_EQ(planeWith(4, true, aligned), 0.5);  // as heavy: uniform
        EXPECT_NEAR(planeWith(8, false, aligned), 0.3, 1e-12);
        EXPECT_NEAR(planeWith(100, false, aligned, 0.004), 2.0 / 7, 0.004);
        EXPECT_NEAR(planeWith(100, true, aligned, 0.004), 2.0 / 7, 0.004);  // lighter by more than chance: kept
    }
    EXPECT_NEAR(planeWith(8, true, false), 0.3, 1e-12);  // a column's own: lighter, kept
    EXPECT_EQ(planeWith(8, true, true), 0.5);             // aligned: lighter by less than chance, uniform
}

// Lighter by the centres a box holds is not lighter where the box is
// thinner than its objects: 100 spheres of radius 0.1 with centres .004 to
// .4 (as above: the plane at 2/7, box 0 holding 71 centres) reach from
// -0.096 to 0.5, and with radius 0.3 every one of them reaches into box 0,
// as into the uniform split's: the start is the uniform split, aligned or
// a column's own. At radius 0.1, 85 reach into box 0 against the uniform
// split's 100: kept.
TEST(InitialSplit, TheHalfStartCountsTheObjectsABoxReachesInto) {
    const Box world{Vec3(-0.5), Vec3(1.5)};
    MachineConfig m = mesh({2, 1, 1});
    m.balance.policy = "sample";
    m.balance.startMix = 0.5;
    m.balance.startLighterOnly = true;
    const Lattice cuts = Lattice::uniform(world, m.dims);
    const auto planeWith = [&](double radius, bool aligned) {
        std::vector<Shape> s;
        for (int i = 0; i < 100; ++i) s.push_back(sphere(Vec3(0.004 * (i + 1), 0.5, 0.5), radius, uint32_t(i)));
        const ObjectBins bins(s, cuts, 1e-9);
        m.balance.startAligned = aligned;
        return initialPlanes(m, cuts, world, bins, 0.025)[0][1];
    };
    for (bool aligned : {false, true}) {
        SCOPED_TRACE(aligned ? "aligned" : "each column its own");
        EXPECT_LT(planeWith(0.1, aligned), 0.5);
        EXPECT_EQ(planeWith(0.3, aligned), 0.5);
    }
    // Each column its own: the machine's heaviest box by reach decides for
    // the columns its start lightens, and a column it leaves as heavy by
    // centres (4 spheres -.45 to -.42: the plane at -.42, box 0 holding all
    // four) still starts uniform beside one it lightens (the 100 above, at
    // radius 0.001).
    MachineConfig two = mesh({2, 2, 1});
    two.balance = m.balance;
    two.balance.startAligned = false;
    const Lattice halves = Lattice::uniform(world, two.dims);
    std::vector<Shape> s;
    for (int i = 0; i < 100; ++i) s.push_back(sphere(Vec3(0.004 * (i + 1), 0.0, 0.5), 0.001, uint32_t(i)));
    for (int i = 0; i < 4; ++i) s.push_back(sphere(Vec3(-0.45 + 0.01 * i, 1.0, 0.5), 0.001, uint32_t(100 + i)));
    const ColumnPlanes p = initialPlanes(two, halves, world, ObjectBins(s, halves, 1e-9), 0.025);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_LT(p[0][1], 0.5);
    EXPECT_EQ(p[1][1], 0.5);
}

// Where the objects crowd, the start packs boxes at the minimum thickness;
// those planes may be a later frame's targets, whose boxes the machine
// checks exactly (withInnerPlanes, no slack). b + m - b may round below m:
// `sample --frames 3` on tetra-3 at 32x32x32 stopped with "box 10 is
// thinner than the minimum thickness" (its boxes at -0.25005 are m =
// 0.003125625 thick, less an ulp). Every start packed at the minimum, at
// many offsets, passes the exact check.
TEST(InitialSplit, BoxesPackedAtTheMinimumPassTheExactCheck) {
    int packed = 0;
    for (int i = 0; i < 200; ++i) {
        const double half = 1.0001 + 1e-5 * i, at = -0.25005 + 1e-4 * i;
        const Box world{Vec3(-half, -1.0, -1.0), Vec3(half, 1.0, 1.0)};
        MachineConfig m = mesh({32, 1, 1});
        m.balance.policy = "median";
        const Lattice cuts = Lattice::uniform(world, m.dims);
        std::vector<Shape> objects;
        for (int k = 0; k < 64; ++k) objects.push_back(sphere(Vec3(at, 0.0, 0.0), 1e-4, uint32_t(k)));
        const ObjectBins bins(objects, cuts, 1e-9);
        const double minThickness = 0.05 * 2 * half / 32;
        const ColumnPlanes start = initialPlanes(m, cuts, world, bins, minThickness);
        std::vector<std::vector<double>> inner;
        for (const auto& p : start) {
            inner.emplace_back(p.begin() + 1, p.end() - 1);
            for (size_t k = 1; k < p.size(); ++k) packed += p[k] - p[k - 1] < 1.5 * minThickness;
        }
        EXPECT_NO_THROW(withInnerPlanes("target boundaries", start, inner, minThickness, 0)) << "offset " << i;
    }
    EXPECT_GT(packed, 200 * 20);  // (the start did pack them: most of the 32 boxes at the minimum)
}

TEST(InitialSplit, AutoStartMixWeighsATestAgainstARaysHop) {
    // A ray's hop on the default machine, by hand: 40 + 40 ns of handling and
    // a 132-byte message (8 of header, 124 of ray) at 1 GB/s, 132 ns: 212 ns.
    MachineConfig m = sampleColumn();
    const std::vector<Shape>& spheres = kTwoSpheres;
    auto mixAt = [&](Picos test) { return startMixFor(withSphereTest(m, test), spheres).mix; };
    EXPECT_EQ(mixAt(10000), 0.5);   // the default's 10 ns: the hops are the work
    EXPECT_EQ(mixAt(70666), 0.5);   // just under a third of the hop (70.67 ns)
    EXPECT_EQ(mixAt(70667), 1.0);   // a third of it: the objects are the work
    EXPECT_NE(startMixFor(m, spheres).why.find("less than a tenth of a ray's hop (212 ns)"), std::string::npos)
        << startMixFor(m, spheres).why;
    // Below a tenth of the hop (21.2 ns) every column starts at the same planes.
    auto alignedAt = [&](Picos test) { return startMixFor(withSphereTest(m, test), spheres).aligned; };
    EXPECT_TRUE(alignedAt(10000));
    EXPECT_TRUE(alignedAt(21199));
    EXPECT_FALSE(alignedAt(21200));
    EXPECT_FALSE(alignedAt(70667));
    EXPECT_NE(startMixFor(m, spheres).why.find("the same planes in every column"), std::string::npos);
    // The half start gives way to the uniform split where it lightens no heaviest box; the median does not.
    auto lighterOnlyAt = [&](Picos test) { return startMixFor(withSphereTest(m, test), spheres).lighterOnly; };
    EXPECT_TRUE(lighterOnlyAt(10000));
    EXPECT_TRUE(lighterOnlyAt(70666));
    EXPECT_FALSE(lighterOnlyAt(70667));
    m.rayBatch = 4;  // a message of 8 + 4 x 124 bytes (504 ns) and its 80 ns of handling, shared by 4 rays: 146 ns
    EXPECT_EQ(mixAt(48666), 0.5);
    EXPECT_EQ(mixAt(48667), 1.0);
    m.rayBatch = 1;
    m.speed = 2;  // the processor's costs halve, the wire's do not: 40 + 132 = 172 ns; a test of 114.667 ns takes 57.333
    EXPECT_EQ(mixAt(114666), 0.5);
    EXPECT_EQ(mixAt(114667), 1.0);
    m.speed = 1;
    m.hopsByLinks = true;  // the sender's engine holds the wire, the receiver's adds latency: 40 + 132 ns
    EXPECT_EQ(mixAt(57333), 0.5);
    EXPECT_EQ(mixAt(57334), 1.0);
    m.hopsByLinks = false;
    // Where a hop's wire time is at least 10 handlings (80 ns: 800 ns, a
    // 132-byte message at 165 MB/s), the links set the frame: the half
    // start gives way to the uniform split (rings-2 on 4x4x4 lost 14 % from
    // it at 100 MB/s); the object median, where the tests are the work, not.
    m.link.bandwidth = 165e6;
    EXPECT_EQ(mixAt(10000), 0.0);
    EXPECT_NE(startMixFor(m, spheres).why.find("its wire time is 10 times its handling (at least 10): the uniform split"),
              std::string::npos)
        << startMixFor(m, spheres).why;
    EXPECT_EQ(mixAt(1000000), 1.0);
    m.link.bandwidth = 166e6;
    EXPECT_EQ(mixAt(10000), 0.5);
    m.hopsByLinks = true;  // (no handling on the processors to weigh the wire against: not this rule)
    m.link.bandwidth = 100e6;
    EXPECT_EQ(mixAt(10000), 0.5);
    m.hopsByLinks = false;
    m.link.bandwidth = 1e9;
    // A column of more than 8 boxes starts uniform whatever the costs: where
    // the hops are the work (a long box carries the rays across its sides)
    // and where the tests are (a thin box costs every ray through it a hop:
    // the paper's machine at N = 16 and 32, doc/balancing.md).
    m.dims = {9, 1, 1};
    EXPECT_EQ(mixAt(10000), 0.0);
    EXPECT_EQ(mixAt(70666), 0.0);
    EXPECT_EQ(mixAt(70667), 0.0);
    m.dims = {8, 1, 1};
    EXPECT_EQ(mixAt(70667), 1.0);
    m.dims = {9, 1, 1};
    EXPECT_NE(startMixFor(m, spheres).why.find("a column has 9 boxes (more than 8): the uniform split"),
              std::string::npos)
        << startMixFor(m, spheres).why;
    m.dims = {8, 16, 16};  // the column's own length counts, along the axis (x)
    EXPECT_EQ(mixAt(10000), 0.5);
    m.balance.axis = 1;
    EXPECT_EQ(mixAt(10000), 0.0);
    m.balance.axis = 0;
    m.dims = {4, 1, 1};
    m.balance.policy = "median";  // by its name, at the object median whatever the costs
    EXPECT_EQ(mixAt(10000), 1.0);
    m.dims = {64, 1, 1};
    EXPECT_EQ(mixAt(10000), 1.0);
    m.dims = {4, 1, 1};
    // chosen once: a mix given stays, and a policy that starts uniform keeps auto (unused)
    m.balance.policy = "sample";
    chooseStartMix(m, spheres);
    EXPECT_EQ(m.balance.startMix, 0.5);
    EXPECT_TRUE(m.balance.startAligned);
    EXPECT_TRUE(m.balance.startLighterOnly);  // (the half start alone)
    EXPECT_FALSE(m.balance.startMixWhy.empty());
    m.balance.startMix = 0.25;
    chooseStartMix(m, spheres);
    EXPECT_EQ(m.balance.startMix, 0.25);
    m.balance.policy = "slide";
    m.balance.startMix = kStartMixAuto;
    chooseStartMix(m, spheres);
    EXPECT_EQ(m.balance.startMix, kStartMixAuto);
}

// --sample-end auto (the default) by the same costs as the start mix: on
// the default machine a ray's hop is 212 ns (above); a test of a third of
// it (70.667 ns) or more makes the tests the work, and sample's gather
// waits for the frame buffer's word (credit); below, it starts once the
// sample's rays are generated. Chosen only for sample, only where it
// gathers (no frame carried), and never over a value given.
TEST(InitialSplit, SampleEndAutoWaitsForTheCreditWhereTheTestsAreTheWork) {
    MachineConfig m = sampleColumn();
    const Scene spheres = viewedAlongX(kTwoSpheres, -1.0);  // (from below the column: its lowest node generates)
    auto endAt = [&](Picos test) {
        MachineConfig c = withSphereTest(m, test);
        chooseSampleEnd(c, spheres);
        EXPECT_FALSE(c.balance.sampleEndWhy.empty());
        return c.balance.sampleCredit;
    };
    ASSERT_TRUE(m.balance.sampleEndAuto);  // (the default)
    EXPECT_FALSE(endAt(10000));
    EXPECT_FALSE(endAt(70666));
    EXPECT_TRUE(endAt(70667));
    chooseSampleEnd(m, spheres);
    EXPECT_EQ(m.balance.sampleEndWhy, "auto: a test (10 ns) costs less than a tenth of a ray's hop (212 ns): generated");
    MachineConfig given = m;  // a value given stays
    given.costs.test[0] = 70667;
    given.balance.sampleEndAuto = false;
    given.balance.sampleCredit = false;
    given.balance.sampleEndWhy.clear();
    chooseSampleEnd(given, spheres);
    EXPECT_FALSE(given.balance.sampleCredit);
    EXPECT_TRUE(given.balance.sampleEndWhy.empty());
    MachineConfig slide = given;  // another policy gathers no sample: auto stays unchosen
    slide.balance.policy = "slide";
    slide.balance.sampleEndAuto = true;
    chooseSampleEnd(slide, spheres);
    EXPECT_FALSE(slide.balance.sampleCredit);
    EXPECT_TRUE(slide.balance.sampleEndWhy.empty());
    MachineConfig carried = slide;  // a frame carried gathers no sample either
    carried.balance.policy = "sample";
    carried.startBoundaries = {{0.25, 0.5, 0.75}};
    chooseSampleEnd(carried, spheres);
    EXPECT_FALSE(carried.balance.sampleCredit);
}

// The view decides too: `generated` starts the column's sum at its lowest
// node, so where only the top nodes generate the sample's rays (the eye
// beyond the column's far end, looking down it) the gather waits for the
// credit, whatever the costs; the same scene seen from below starts on
// generating. With one box along the axis there is no gather to start.
TEST(InitialSplit, SampleEndAutoWaitsForTheCreditWhereOnlyTheTopNodesGenerateTheSample) {
    MachineConfig m = sampleColumn();
    const Scene below = viewedAlongX(kTwoSpheres, -1.0), above = viewedAlongX(kTwoSpheres, 2.0);
    EXPECT_FALSE(onlyTopNodesGenerateSample(m, below));
    EXPECT_TRUE(onlyTopNodesGenerateSample(m, above));
    MachineConfig fromBelow = m, fromAbove = m;
    chooseSampleEnd(fromBelow, below);
    chooseSampleEnd(fromAbove, above);
    EXPECT_FALSE(fromBelow.balance.sampleCredit);
    EXPECT_TRUE(fromAbove.balance.sampleCredit);
    EXPECT_NE(fromAbove.balance.sampleEndWhy.find("only the columns' top nodes generate primary rays of the sample"),
              std::string::npos)
        << fromAbove.balance.sampleEndWhy;
    MachineConfig given = m;  // a value given stays
    given.balance.sampleEndAuto = false;
    chooseSampleEnd(given, above);
    EXPECT_FALSE(given.balance.sampleCredit);
    MachineConfig one = m;  // one box along the axis: it is the top one, and the lowest
    one.dims = {1, 4, 1};
    one.balance.axis = 0;
    EXPECT_FALSE(onlyTopNodesGenerateSample(one, above));
}

// Where the tests are the work, sample's start weighs where the primary
// rays enter too (StartMix::generation): by hand, four centres at x = .1
// to .4 on a column of two boxes, every ray entering at x = 0 (seen along
// x). At weight 0.5 the plane is the least x where half the centres' share
// plus half the entries' (all of them, from x = 0 on) passes 1/2: the
// first centre, 0.1; the object median alone (no camera, or weight 0) puts
// it at the third, 0.3.
TEST(InitialSplit, WherePrimaryRaysEnterWeighsInWhereTheTestsAreTheWork) {
    const Box world{Vec3(0.0), Vec3(1.0)};
    MachineConfig m = mesh({2, 1, 1});
    m.balance.policy = "sample";
    const Lattice cuts = Lattice::uniform(world, m.dims);
    std::vector<Shape> objects;
    for (int i = 0; i < 4; ++i) objects.push_back(sphere(Vec3(0.1 * (i + 1), 0.5, 0.5), 0.01, uint32_t(i)));
    const ObjectBins bins(objects, cuts, 1e-9);
    const Camera along(View{Vec3(-1.3, 0.5, 0.5), Vec3(0.5, 0.5, 0.5), Vec3(0, 0, 1), 20}, 16, 16);
    const std::vector<std::vector<double>> entries = primaryEntries(along, world, cuts, ColumnGeometry(0, m.dims));
    ASSERT_EQ(entries.size(), 1u);
    ASSERT_EQ(entries[0].size(), 256u);
    for (double x : entries[0]) EXPECT_NEAR(x, 0.0, 1e-9);
    m.balance.startMix = 1;
    m.balance.startGeneration = 0.5;
    EXPECT_NEAR(initialPlanes(m, cuts, world, bins, 0.025, &along)[0][1], 0.1, 1e-9);
    EXPECT_NEAR(initialPlanes(m, cuts, world, bins, 0.025)[0][1], 0.3, 1e-9);
    m.balance.startGeneration = 0;
    EXPECT_NEAR(initialPlanes(m, cuts, world, bins, 0.025, &along)[0][1], 0.3, 1e-9);
    // The weight: a ray's generation against itself and 8 tests, at the
    // nodes' speed (the paper's machine: 36 us against 8 x 17 us).
    m.costs.rayGen = 36000000;
    m.costs.test[0] = 17000000;
    EXPECT_DOUBLE_EQ(generationWeight(m, 17000000), 36.0 / (36 + 8 * 17));
    m.speed = 2;
    EXPECT_DOUBLE_EQ(generationWeight(m, 8500000), 36.0 / (36 + 8 * 17));  // (the test as testAgainstHop gives it, at speed)
    // auto: the object median and that weight where the tests are the work;
    // where the hops are, none.
    m.speed = 1;
    m.balance.startMix = kStartMixAuto;
    chooseStartMix(m, objects);
    EXPECT_EQ(m.balance.startMix, 1.0);
    EXPECT_DOUBLE_EQ(m.balance.startGeneration, 36.0 / (36 + 8 * 17));
    EXPECT_NE(m.balance.startMixWhy.find("where the primary rays enter"), std::string::npos) << m.balance.startMixWhy;
    MachineConfig cheap = mesh({2, 1, 1});
    cheap.balance.policy = "sample";
    chooseStartMix(cheap, objects);
    EXPECT_EQ(cheap.balance.startGeneration, 0.0);
}

TEST(InitialSplit, EveryPrimaryRayGoesToTheNodeThatOwnsItsStart) {
    ProceduralParams p;
    p.spheres = 10;
    p.eye = Vec3(0.5, 0.45, 0.3);  // inside the world: rays start at the eye's node
    Scene scene = makeProceduralScene(p);
    for (const View& v : {scene.view, View{Vec3(-1.3, 0.4, 0.6), Vec3(0.5, 0.5, 0.5), Vec3(0, 0, 1), 70}}) {
        const Camera camera(v, 24, 20);
        const Box world = scene.worldBox();
        const MachineConfig m = mesh({3, 2, 2});
        const ColumnGeometry g(0, m.dims);
        const Lattice cuts = Lattice::uniform(world, m.dims);
        ColumnPlanes planes(size_t(g.count()), cuts.planes(0));
        planes[1] = {world.lo.x, 0.1, 0.2, world.hi.x};  // one column split elsewhere along x
        const PrimaryRays r = assignPrimaryRays(camera, world, cuts, g, planes);
        std::vector<uint32_t> all;
        for (size_t i = 0; i < r.perNode.size(); ++i) {
            const Box box = nodeBox(cellAt(i, m.dims), cuts, g, planes);
            for (uint32_t pixel : r.perNode[i]) {
                all.push_back(pixel);
                const RayJob j = primaryJob(camera, int(pixel % 24), int(pixel / 24), world);
                const Interval owned = boxInterval(j.ray, box);
                EXPECT_TRUE(owned.lo <= j.t0 && j.t0 < owned.hi) << "pixel " << pixel << " at node " << i;
            }
        }
        for (const RayJob& j : r.misses) all.push_back(j.pixel);
        if (v.from == p.eye) {
            EXPECT_TRUE(r.misses.empty());  // from inside the world no ray misses it
        }
        std::sort(all.begin(), all.end());
        std::vector<uint32_t> each(24 * 20);
        std::iota(each.begin(), each.end(), 0u);
        EXPECT_EQ(all, each);  // every pixel once
    }
}

TEST(InitialSplit, TheCreditSharesSumToExactlyOne) {
    const std::vector<std::vector<uint32_t>> perNode{{1, 2, 3}, {}, {4}, {5, 6, 7, 8, 9}};
    const CreditShares s = shareCredit(perNode, 40);
    EXPECT_EQ(s.exp, (std::vector<int>{2 + 2, 0, 2 + 0, 2 + 3}));  // 3 nodes with rays: 2^-2 each
    Credit total(40);
    total.add(s.host);  // 1 - 3/4
    EXPECT_EQ(s.host.value(), 0.25);
    for (size_t i = 0; i < perNode.size(); ++i) {
        total.add(s.remainder[i]);
        for (size_t k = 0; k < perNode[i].size(); ++k) total.add(s.exp[i]);
    }
    EXPECT_TRUE(total.isOne());
}

// ---- Between frames (between_frames.h) ----

namespace {

// These reports' frames last nanoseconds: the machine they are of moves its
// planes for nothing (no latency, no handling), so a move is judged by the
// frame it makes alone (what a move costs: Resplit.GettingToNewPlanes...).
MachineConfig freeMoves(std::array<int, 3> dims, int axis = 0) {
    MachineConfig m = mesh(dims, axis);
    m.link.latency = 0;
    m.costs.send = m.costs.recv = 0;
    return m;
}

// A report of a 3x1x1 mesh along x: boundary 1 from `b1` (at time 0) to
// `b1end` (at 5 ns), boundary 2 at 2/3 throughout; the nodes' busy times.
nlohmann::json reportJson(double renderNs, double b1, double b1end, std::array<double, 3> busy) {
    nlohmann::json r;
    r["render_time_ns"] = renderNs;
    r["config"]["mesh"] = {3, 1, 1};
    r["config"]["balance"]["axis"] = "x";
    r["boundaries"] = {{{"column", {0, 0}}, {"index", 1}, {"history", {{0, b1}, {5, b1end}}}},
                       {{"column", {0, 0}}, {"index", 2}, {"history", {{0, 2.0 / 3}}}}};
    const double planes[] = {0, b1end, 2.0 / 3, 1};
    for (int k = 0; k < 3; ++k)
        r["nodes"].push_back({{"node", {k, 0, 0}}, {"box", {{planes[k], 0, 0}, {planes[k + 1], 1, 1}}}, {"busy_ns", busy[size_t(k)]}});
    return r;
}
// The same, as the frame state read back from it.
FrameState report(double renderNs, double b1, double b1end, std::array<double, 3> busy) {
    return frameStateFromReport(reportJson(renderNs, b1, b1end, busy));
}

}  // namespace

TEST(BetweenFrames, BoundariesReadBackFromAReport) {
    const MachineConfig m = mesh({3, 1, 1});
    const FrameState r = report(10, 0.3, 0.4, {1, 1, 1});
    EXPECT_EQ(lastBoundaries(r, m), (InnerPlanes{{0.4, 2.0 / 3}}));
    EXPECT_EQ(lastBoundaries(r, m, true), (InnerPlanes{{0.3, 2.0 / 3}}));
    EXPECT_THROW(lastBoundaries(r, mesh({3, 1, 1}, 1)), std::runtime_error);  // another axis
    EXPECT_THROW(lastBoundaries(r, mesh({2, 1, 1})), std::runtime_error);     // another mesh
    nlohmann::json broken = reportJson(10, 0.3, 0.4, {1, 1, 1});
    broken.erase("boundaries");
    EXPECT_THROW(frameStateFromReport(broken), std::runtime_error);
    FrameState missing = r;
    missing.boundaries.pop_back();
    EXPECT_THROW(lastBoundaries(missing, m), std::runtime_error);
}

TEST(BetweenFrames, ResplitEvensTheBusiestNodeByTheForecast) {
    // Planes at 1/3 and 2/3 throughout; busy 2, 1, 1, each spread over its
    // box (no rays cut in this report): the dearest node is least at 4/3,
    // with planes at 2/9 and 5/9 (node 0's 2 over [0, 1/3] reach 4/3 at 2/9;
    // its last 2/3 and node 1's 1 over [1/3, 2/3] reach 4/3 more at 5/9).
    // The search places planes on the work's bins (1/384 here).
    const ResplitChoice c = resplitChoice(report(10, 1.0 / 3, 1.0 / 3, {2, 1, 1}), freeMoves({3, 1, 1}));
    ASSERT_EQ(c.planes.size(), 1u);
    ASSERT_EQ(c.planes[0].size(), 2u);
    EXPECT_NEAR(c.planes[0][0], 2.0 / 9, 1.0 / 384);
    EXPECT_NEAR(c.planes[0][1], 5.0 / 9, 1.0 / 384);
    EXPECT_NEAR(c.heldNs, 2, 1e-9);
    EXPECT_NEAR(c.forecastNs, 4.0 / 3, 3.0 / 384);
    EXPECT_STREQ(c.what, "aligned");  // (one column: both searches agree, the aligned one, tried first, is kept)
}

TEST(BetweenFrames, ResplitPlacesTheWorkWhereItHappened) {
    // As above, but node 0's work happened where its profile says: 1.5 of
    // its 2 in [0, 0.1) (bins of 0.05 from 0: bins 0 and 1, 0.75 each), the
    // rest (0.5) spread over its box [0, 1/3]. Total 4, 4/3 per node: the
    // first plane where 4/3 lies below: 1.5 by 0.1 already, so within
    // [0.05, 0.1): 0.75 + 0.5 x 0.05 / (1/3) below 0.05 (0.825), and
    // 0.75 / 0.05 + 0.5 / (1/3) per unit above it: (4/3 - 0.825) / 16.5.
    nlohmann::json r = reportJson(10, 1.0 / 3, 1.0 / 3, {2, 1, 1});
    r["nodes"][0]["work_by_position"] = {{"axis_from", 0.0}, {"bin_width", 0.05}, {"first_bin", 0}, {"ns", {0.75, 0.75}}};
    const InnerPlanes t = resplitTargets(frameStateFromReport(r), freeMoves({3, 1, 1}));
    ASSERT_EQ(t.size(), 1u);
    EXPECT_NEAR(t[0][0], 0.05 + (4.0 / 3 - 0.825) / 16.5, 1.0 / 384);
    // The second: 2 below 1/3 (node 0), then node 1's 1 over [1/3, 2/3]: 8/3 at 1/3 + 2/9.
    EXPECT_NEAR(t[0][1], 5.0 / 9, 1.0 / 384);
}

TEST(BetweenFrames, ResplitHoldsThePlanesWhenTheForecastGainsLittle) {
    // Busy 1.04, 1, 1: the best forecast, 3.04 / 3 each, is 2.6 % shorter
    // than holding (1.04), less than kMinForecastGain: the planes hold, where
    // the frame ended them.
    const ResplitChoice c = resplitChoice(report(10, 0.30, 0.31, {1.04, 1, 1}), freeMoves({3, 1, 1}));
    EXPECT_STREQ(c.what, "held");
    EXPECT_EQ(c.planes, (InnerPlanes{{0.31, 2.0 / 3}}));
    EXPECT_NEAR(c.forecastNs, c.heldNs, 1e-12);
    // At 1.1 it moves.
    EXPECT_STRNE(resplitChoice(report(10, 0.30, 0.31, {1.1, 1, 1}), freeMoves({3, 1, 1})).what, "held");
}

TEST(BetweenFrames, ResplitHoldsTheFastestFrameOnceAResplitLoses) {
    const MachineConfig m = freeMoves({3, 1, 1});
    ResplitSequence s(m);
    const auto first = s.next(report(100, 0.30, 0.31, {2, 1, 1}), 1);  // re-split after frame 1
    ASSERT_TRUE(first);
    EXPECT_EQ(s.said().at("next"), "aligned");
    const auto second = s.next(report(80, 0.31, 0.32, {1.5, 1, 1}), 2);  // faster: re-split again
    ASSERT_TRUE(second);
    EXPECT_FALSE(s.startsAfresh());
    EXPECT_EQ(*second, resplitTargets(report(80, 0.31, 0.32, {1.5, 1, 1}), m));
    const auto third = s.next(report(90, 0.32, 0.33, {1.5, 1, 1}), 3);  // slower: back to frame 2's planes, held
    ASSERT_TRUE(third);
    EXPECT_EQ(*third, (InnerPlanes{{0.32, 2.0 / 3}}));
    EXPECT_EQ(s.said().at("next"), "the fastest frame's planes");
    EXPECT_EQ(*s.next(report(70, 0.5, 0.5, {3, 1, 1}), 4), *third);
    EXPECT_EQ(s.said().at("next"), "held");
}

TEST(BetweenFrames, MeasuredHoldsItsStartingSplitWhenReSplittingDoesNotPay) {
    // measured's frame 1 was the starting split itself: when neither of the
    // first two re-split frames beats it, the start is held, with no trial.
    MachineConfig m = freeMoves({3, 1, 1});
    m.balance.policy = "measured";
    ResplitSequence s(m);
    ASSERT_TRUE(s.next(report(100, 0.30, 0.30, {2, 1, 1}), 1));
    ASSERT_TRUE(s.next(report(110, 0.30, 0.31, {1, 1, 1}), 2));
    const auto held = s.next(report(105, 0.31, 0.32, {1, 1, 1}), 3);
    ASSERT_TRUE(held);
    EXPECT_FALSE(s.startsAfresh());
    EXPECT_EQ(*held, (InnerPlanes{{0.30, 2.0 / 3}}));  // where frame 1 started
    EXPECT_EQ(*s.next(report(100, 0.30, 0.30, {5, 1, 1}), 4), *held);
}

TEST(BetweenFrames, ResplitThatDoesNotPayTriesTheStartingSplit) {
    const MachineConfig m = freeMoves({3, 1, 1});
    for (const double trial : {95.0, 105.0}) {
        ResplitSequence s(m);
        s.next(report(100, 0.30, 0.31, {2, 1, 1}), 1);
        ASSERT_TRUE(s.next(report(120, 0.31, 0.32, {1, 1, 1}), 2));  // slower than frame 1: one more try
        const auto start = s.next(report(110, 0.32, 0.33, {1, 1, 1}), 3);  // still slower: the split frame 1 started from
        ASSERT_TRUE(start);
        EXPECT_EQ(*start, (InnerPlanes{{0.30, 2.0 / 3}}));
        EXPECT_TRUE(s.startsAfresh());
        const auto after = s.next(report(trial, 0.30, 0.30, {1, 1, 1}), 4);
        if (trial < 100) {  // the starting split beat frame 1: held
            ASSERT_TRUE(after);
            EXPECT_EQ(*after, *start);
        } else {  // it did not: every later frame is frame 1 again
            EXPECT_FALSE(after);
            EXPECT_FALSE(s.next(report(50, 0.30, 0.30, {1, 1, 1}), 5));
        }
    }
}

// --polish-tries: once the sequence would hold, frames that each try a
// move of the planes held (between_frames.h, "Polish"), keeping the faster.
TEST(BetweenFrames, PolishTriesMovesAndKeepsTheFasterFrames) {
    MachineConfig m = freeMoves({3, 1, 1});
    m.balance.polishTries = 3;
    ResplitSequence s(m);
    ASSERT_TRUE(s.next(report(100, 0.10, 0.31, {2, 1, 1}), 1));
    ASSERT_TRUE(s.next(report(80, 0.31, 0.32, {1.5, 1, 1}), 2));  // faster: re-split again
    // Slower: frame 2's planes, {0.32, 2/3}, are held, and polished. Its
    // busiest node, 0, has one neighbour: its upper face moves down by
    // kPolishShrink of the thinner box it bounds (0.32 against 0.347).
    const auto first = s.next(report(90, 0.32, 0.33, {1.5, 1, 1}), 3);
    ASSERT_TRUE(first);
    EXPECT_EQ(s.said().at("next"), "a move tried");
    EXPECT_EQ(s.said().at("held_ns"), 80);
    const double kept = 0.32 - kPolishShrink * 0.32;
    EXPECT_NEAR((*first)[0][0], kept, 1e-12);
    EXPECT_EQ((*first)[0][1], 2.0 / 3);
    // That frame is faster: kept. Its busiest node, 1, has two neighbours;
    // the next move shifts every plane towards the axis's start by the same
    // share of the thinner box each bounds.
    const auto second = s.next(report(70, 0.32, kept, {1, 1.2, 1}), 4);
    ASSERT_TRUE(second);
    EXPECT_EQ(s.said().at("held_ns"), 70);
    EXPECT_NEAR((*second)[0][0], kept - kPolishShrink * kept, 1e-12);
    EXPECT_NEAR((*second)[0][1], 2.0 / 3 - kPolishShrink / 3, 1e-12);
    // Slower: back to the planes kept, and the third move shifts them
    // towards the axis's end.
    const auto third = s.next(report(75, kept, 0.25, {1, 1.2, 1}), 5);
    ASSERT_TRUE(third);
    EXPECT_EQ(s.said().at("held_ns"), 70);
    EXPECT_NEAR((*third)[0][0], kept + kPolishShrink * kept, 1e-12);
    EXPECT_NEAR((*third)[0][1], 2.0 / 3 + kPolishShrink / 3, 1e-12);
    // Slower again, and the tries are spent: the planes kept are held.
    const auto held = s.next(report(72, kept, 0.3, {1, 1.2, 1}), 6);
    ASSERT_TRUE(held);
    EXPECT_EQ(s.said().at("next"), "held");
    EXPECT_NEAR((*held)[0][0], kept, 1e-12);
    EXPECT_EQ(*s.next(report(71, kept, kept, {1, 1.2, 1}), 7), *held);
    // Where the busiest node is the last along the column, its lower face
    // moves up: by kPolishShrink of its own box (1/3, the thinner).
    ResplitSequence last(m);
    last.next(report(100, 0.10, 0.31, {2, 1, 1}), 1);
    last.next(report(80, 0.31, 0.32, {1, 1, 1.5}), 2);
    const auto up = last.next(report(90, 0.32, 0.33, {1.5, 1, 1}), 3);
    ASSERT_TRUE(up);
    EXPECT_EQ(last.said().at("next"), "a move tried");
    EXPECT_EQ((*up)[0][0], 0.32);
    EXPECT_NEAR((*up)[0][1], 2.0 / 3 + kPolishShrink / 3, 1e-12);
    // Without --polish-tries the same frames hold frame 2's planes at once.
    const MachineConfig off = freeMoves({3, 1, 1});  // (the sequence keeps a reference to it)
    ResplitSequence plain(off);
    plain.next(report(100, 0.10, 0.31, {2, 1, 1}), 1);
    plain.next(report(80, 0.31, 0.32, {1.5, 1, 1}), 2);
    EXPECT_EQ(*plain.next(report(90, 0.32, 0.33, {1.5, 1, 1}), 3), (InnerPlanes{{0.32, 2.0 / 3}}));
}

// A move is tried only where the forecast puts it kPolishRoom faster than
// the unbalanced split (here the split frame 1 started from, as measured's
// is). Frame 3's busy times (1.5, 1, 1), spread over boxes 0.32, 0.347 and
// 0.333: node 0's box shrunk by 0.0256 is forecast at 1.38 (node 0), 8 %
// faster than the planes held (1.5). From frame 1 started at 0.10 (node 1
// then forecast at 1.5 x 0.22 / 0.32 + 1 = 2.03) that is room; started
// where the planes are held, it is not (0.9 x 1.5 < 1.38).
TEST(BetweenFrames, PolishTriesOnlyWithRoomUnderTheUnbalancedFrame) {
    MachineConfig m = freeMoves({3, 1, 1});
    m.balance.polishTries = 1;
    const InnerPlanes shrunk{{0.32 - kPolishShrink * 0.32, 2.0 / 3}};
    for (const double start : {0.10, 0.32}) {
        ResplitSequence s(m);
        s.next(report(100, start, 0.31, {2, 1, 1}), 1);
        s.next(report(80, 0.31, 0.32, {1.5, 1, 1}), 2);
        const auto next = s.next(report(90, 0.32, 0.32, {1.5, 1, 1}), 3);
        ASSERT_TRUE(next);
        if (start == 0.10) {
            EXPECT_EQ(s.said().at("next"), "a move tried");
            EXPECT_NEAR((*next)[0][0], shrunk[0][0], 1e-12);
        } else {
            EXPECT_EQ(s.said().at("next"), "the fastest frame's planes");  // (held, no move tried)
            EXPECT_EQ(*next, (InnerPlanes{{0.32, 2.0 / 3}}));
        }
    }
}

// A move that would leave a box thinner than the minimum is not tried.
TEST(BetweenFrames, PolishTriesNoMoveBelowTheMinimumThickness) {
    MachineConfig m = freeMoves({3, 1, 1});
    m.balance.polishTries = 1;
    m.balance.minThickness = 0.95;  // of the uniform split's 1/3: the boxes held are 0.32, 0.347 and 0.333
    ResplitSequence s(m);
    s.next(report(100, 0.10, 0.31, {2, 1, 1}), 1);
    s.next(report(80, 0.31, 0.32, {1.5, 1, 1}), 2);
    const auto held = s.next(report(90, 0.32, 0.33, {1.5, 1, 1}), 3);
    ASSERT_TRUE(held);
    EXPECT_EQ(*held, (InnerPlanes{{0.32, 2.0 / 3}}));
    EXPECT_EQ(s.said().at("next"), "held");  // (no move tried: none fits)
    EXPECT_FALSE(s.said().contains("held_ns"));
    // With room, the same frames try a move.
    m.balance.minThickness = 0.05;
    ResplitSequence roomy(m);
    roomy.next(report(100, 0.10, 0.31, {2, 1, 1}), 1);
    roomy.next(report(80, 0.31, 0.32, {1.5, 1, 1}), 2);
    roomy.next(report(90, 0.32, 0.33, {1.5, 1, 1}), 3);
    EXPECT_EQ(roomy.said().at("next"), "a move tried");
}

// --balance recommended: sample on columns of 2 to 8 boxes along the
// axis, measured on longer ones (sample's first frame lost at 3 of 62 SPD
// points on columns of 16 to 64 boxes, measured's at none: doc/balancing.md,
// "The recommended policy"), none on columns of one box (no face to move).
// The column's length is along the axis.
TEST(RecommendedPolicy, NoneOnOneBoxSampleOnAtMostEightBoxesElseMeasured) {
    EXPECT_STREQ(recommendedPolicy({8, 8, 8}, 0).policy, "sample");
    EXPECT_STREQ(recommendedPolicy({1, 1, 2}, 2).policy, "sample");
    EXPECT_STREQ(recommendedPolicy({1, 1, 2}, 0).policy, "none");  // (a column of one box: nothing to move)
    EXPECT_EQ(recommendedPolicy({64, 1, 1}, 2).why, "none: columns of 1 box: no boundary along the axis to move");
    EXPECT_STREQ(recommendedPolicy({9, 1, 1}, 0).policy, "measured");
    EXPECT_STREQ(recommendedPolicy({2, 2, 32}, 0).policy, "sample");
    EXPECT_STREQ(recommendedPolicy({2, 2, 32}, 2).policy, "measured");
    EXPECT_STREQ(recommendedPolicy({16, 16, 4}, 2).policy, "sample");
    EXPECT_EQ(recommendedPolicy({4, 4, 4}, 1).why, "sample: columns of 4 boxes (at most 8)");
    EXPECT_STREQ(recommendedPolicy({1, 1, 1}, 0).policy, "none");
    EXPECT_EQ(recommendedPolicy({64, 1, 1}, 0).why,
              "measured: columns of 64 boxes (more than 8): the first frame keeps its split");
}
