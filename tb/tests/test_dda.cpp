// 3D-DDA: the cells Lattice::walk visits, with their ray segments, are
// exactly those a brute-force ray/cell overlap test over every cell finds,
// in the same order, for random and degenerate rays.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "lattice.h"

using namespace rt;

namespace {

struct Visit {
    Cell cell;
    Interval seg;
    bool operator==(const Visit& o) const { return cell == o.cell && seg.lo == o.seg.lo && seg.hi == o.seg.hi; }
};

std::vector<Visit> walked(const Lattice& L, const Ray& r, double t0, double t1) {
    std::vector<Visit> v;
    L.walk(r, t0, t1, [&](const Cell& c, const Interval& s) {
        v.push_back({c, s});
        return true;
    });
    return v;
}

// Every cell of the lattice, tested on its own.
std::vector<Visit> bruteForce(const Lattice& L, const Ray& r, double t0, double t1) {
    std::vector<Visit> v;
    for (int z = 0; z < L.cells(2); ++z)
        for (int y = 0; y < L.cells(1); ++y)
            for (int x = 0; x < L.cells(0); ++x) {
                const Interval s = L.segment(r, {x, y, z}, t0, t1);
                if (!s.empty()) v.push_back({{x, y, z}, s});
            }
    std::sort(v.begin(), v.end(), [](const Visit& a, const Visit& b) { return a.seg.lo < b.seg.lo; });
    return v;
}

void expectSame(const Lattice& L, const Ray& r, double t0, double t1) {
    const auto a = walked(L, r, t0, t1), b = bruteForce(L, r, t0, t1);
    ASSERT_EQ(a.size(), b.size()) << "o=(" << r.o.x << "," << r.o.y << "," << r.o.z << ") d=(" << r.d.x << ","
                                  << r.d.y << "," << r.d.z << ")";
    for (size_t i = 0; i < a.size(); ++i) ASSERT_TRUE(a[i] == b[i]) << "visit " << i;
    // Segments chain: each starts where the previous ended.
    for (size_t i = 1; i < a.size(); ++i) ASSERT_EQ(a[i].seg.lo, a[i - 1].seg.hi);
    // Geometry, independently of the t rule: a segment's midpoint lies in its cell.
    for (const Visit& v : a) {
        const Vec3 m = r.at(0.5 * (v.seg.lo + v.seg.hi));
        const Box b = L.cellBox(v.cell);
        const double tol = 1e-9 * (1 + glm::length(m));
        for (int k = 0; k < 3; ++k) {
            ASSERT_GE(m[k], b.lo[k] - tol);
            ASSERT_LE(m[k], b.hi[k] + tol);
        }
    }
}

std::vector<Cell> cellsOf(const Lattice& L, const Ray& r, double t0, double t1) {
    std::vector<Cell> c;
    for (const Visit& v : walked(L, r, t0, t1)) c.push_back(v.cell);
    return c;
}

constexpr double kInf = std::numeric_limits<double>::infinity();
const Box kBox{Vec3(0.0), Vec3(4.0)};

}  // namespace

TEST(Dda, TenThousandRandomRaysMatchBruteForce) {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> u(-1, 5), dir(-1, 1);
    std::uniform_int_distribution<int> res(1, 7), pick(0, 5);
    for (int i = 0; i < 10000; ++i) {
        Lattice L;
        if (i % 2) {
            L = Lattice::uniform(Box{Vec3(-0.3, 0.1, 0.0), Vec3(3.7, 2.0, 4.5)}, {res(rng), res(rng), res(rng)});
        } else {  // irregular planes, as a partition has
            std::array<std::vector<double>, 3> p;
            for (int a = 0; a < 3; ++a) {
                p[a] = {0.0, 4.0};
                for (int k = res(rng); k > 1; --k) p[a].push_back(std::uniform_real_distribution<double>(0.01, 3.99)(rng));
                std::sort(p[a].begin(), p[a].end());
                p[a].erase(std::unique(p[a].begin(), p[a].end()), p[a].end());
            }
            L = Lattice(p);
        }
        Vec3 d(dir(rng), dir(rng), dir(rng));
        const int z = pick(rng);  // sometimes zero one or two direction components
        if (z < 3) d[z] = 0;
        if (z == 0) d[1] = 0;
        if (d == Vec3(0.0)) d.x = 1;
        const Ray r(Vec3(u(rng), u(rng), u(rng)), glm::normalize(d));
        const double t0 = (i % 3) ? 0.0 : std::uniform_real_distribution<double>(-2, 3)(rng);
        const double t1 = (i % 5) ? kInf : t0 + std::uniform_real_distribution<double>(0, 4)(rng);
        expectSame(L, r, t0, t1);
        if (HasFatalFailure()) return;
    }
}

TEST(Dda, AxisParallelRays) {
    const Lattice L = Lattice::uniform(kBox, {4, 4, 4});
    expectSame(L, Ray({-1, 0.5, 0.5}, {1, 0, 0}), 0, kInf);
    expectSame(L, Ray({0.5, 5, 2.5}, {0, -1, 0}), 0, kInf);
    EXPECT_EQ(cellsOf(L, Ray({-1, 0.5, 0.5}, {1, 0, 0}), 0, kInf),
              (std::vector<Cell>{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}));
}

TEST(Dda, RayLyingInAGridPlaneBelongsToTheUpperCell) {
    // y == 2 exactly is a plane between cells 1 and 2: half-open, it is cell 2's.
    const Lattice L = Lattice::uniform(kBox, {4, 4, 4});
    const Ray r({-1, 2, 3}, {1, 0, 0});
    expectSame(L, r, 0, kInf);
    EXPECT_EQ(cellsOf(L, r, 0, kInf), (std::vector<Cell>{{0, 2, 3}, {1, 2, 3}, {2, 2, 3}, {3, 2, 3}}));
    // On the outer top face (y == 4) the ray is outside.
    EXPECT_TRUE(cellsOf(L, Ray({-1, 4, 3}, {1, 0, 0}), 0, kInf).empty());
}

TEST(Dda, ThroughEdgesAndCornersStepsDiagonally) {
    const Lattice L = Lattice::uniform(kBox, {4, 4, 4});
    const Ray edge({0.5, 0.5, 0.5}, glm::normalize(Vec3(1, 1, 0)));  // crosses cell edges at (1,1), (2,2)
    expectSame(L, edge, 0, kInf);
    EXPECT_EQ(cellsOf(L, edge, 0, kInf), (std::vector<Cell>{{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {3, 3, 0}}));
    const Ray corner({0.5, 0.5, 0.5}, glm::normalize(Vec3(1, 1, 1)));
    expectSame(L, corner, 0, kInf);
    EXPECT_EQ(cellsOf(L, corner, 0, kInf), (std::vector<Cell>{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}));
    const Ray mixed({0.5, 3.5, 0.5}, glm::normalize(Vec3(1, -1, 0)));
    expectSame(L, mixed, 0, kInf);
    EXPECT_EQ(cellsOf(L, mixed, 0, kInf), (std::vector<Cell>{{0, 3, 0}, {1, 2, 0}, {2, 1, 0}, {3, 0, 0}}));
    // Starting exactly on a grid corner.
    expectSame(L, Ray({2, 2, 2}, glm::normalize(Vec3(-1, 1, -1))), 0, kInf);
}

TEST(Dda, StartingOnABoxFace) {
    const Lattice L = Lattice::uniform(kBox, {4, 4, 4});
    const Ray r({-2, 1.5, 1.5}, {1, 0, 0});
    const double tFace = r.tAt(0, 0.0);  // exactly the box's entry parameter
    expectSame(L, r, tFace, kInf);
    EXPECT_EQ(cellsOf(L, r, tFace, kInf).front(), (Cell{0, 1, 1}));
    // Starting exactly on the exit face: nothing left to visit.
    EXPECT_TRUE(cellsOf(L, r, r.tAt(0, 4.0), kInf).empty());
    // Starting on an inner face, moving backwards: the cell below owns it.
    const Ray back({3.5, 1.5, 1.5}, {-1, 0, 0});
    EXPECT_EQ(cellsOf(L, back, back.tAt(0, 2.0), kInf).front(), (Cell{1, 1, 1}));
}

TEST(Dda, GrazingABoxEdge) {
    const Lattice L = Lattice::uniform(kBox, {4, 4, 4});
    // Along the edge y = 0 (inside, half-open), z = 4 (outside): no cells.
    expectSame(L, Ray({-1, 0, 4}, {1, 0, 0}), 0, kInf);
    EXPECT_TRUE(cellsOf(L, Ray({-1, 0, 4}, {1, 0, 0}), 0, kInf).empty());
    // Along the edge y = 0, z = 0: the lowest row.
    EXPECT_EQ(cellsOf(L, Ray({-1, 0, 0}, {1, 0, 0}), 0, kInf).size(), 4u);
    // A diagonal ray touching the box only at its corner (4, 4, z).
    const Ray touch({3, 5, 1}, glm::normalize(Vec3(1, -1, 0)));
    expectSame(L, touch, 0, kInf);
    EXPECT_TRUE(cellsOf(L, touch, 0, kInf).empty());
}

TEST(Dda, StopsWhenVisitSaysSo) {
    const Lattice L = Lattice::uniform(kBox, {4, 4, 4});
    int n = 0;
    L.walk(Ray({-1, 0.5, 0.5}, {1, 0, 0}), 0, kInf, [&](const Cell&, const Interval&) { return ++n < 2; });
    EXPECT_EQ(n, 2);
}

TEST(Dda, LocateAgreesWithWalk) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 5), dir(-1, 1);
    const Lattice L = Lattice::uniform(kBox, {5, 3, 4});
    for (int i = 0; i < 2000; ++i) {
        const Ray r(Vec3(u(rng), u(rng), u(rng)), glm::normalize(Vec3(dir(rng), dir(rng), dir(rng))));
        for (const Visit& v : walked(L, r, 0, kInf)) {
            ASSERT_EQ(L.locate(r, v.seg.lo), std::optional<Cell>(v.cell));
        }
    }
}

// Lattice::locate guesses a cell from the point's coordinates and checks
// the guess against the planes: the cell it names must be the one whose
// segment (Lattice::segment, the slab rule) holds t, on evenly spaced planes
// and uneven ones (a partition after boundaries slid), and at the parameters
// where the guess is hardest: a plane's own crossing and the doubles beside it.
TEST(Dda, LocateNamesTheCellWhoseSegmentHoldsT) {
    const Lattice even = Lattice::uniform(kBox, {5, 3, 4});
    const Lattice uneven({std::vector<double>{0, 0.1, 0.15, 2.9, 4}, std::vector<double>{0, 3.5, 3.6, 4},
                          std::vector<double>{0, 1, 1.0000001, 1.5, 3.99, 4}});
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 5), dir(-1, 1), t(-2, 12);
    for (const Lattice* L : {&even, &uneven}) {
        auto owner = [&](const Ray& r, double at) {
            std::optional<Cell> found;
            for (int z = 0; z < L->cells(2); ++z)
                for (int y = 0; y < L->cells(1); ++y)
                    for (int x = 0; x < L->cells(0); ++x) {
                        const Interval s = L->segment(r, {x, y, z}, -kInf, kInf);
                        if (s.lo <= at && at < s.hi) found = Cell{x, y, z};
                    }
            return found;
        };
        int inside = 0;
        for (int i = 0; i < 3000; ++i) {
            Vec3 d(dir(rng), dir(rng), dir(rng));
            if (i % 7 == 0) d[i % 3] = 0;  // parallel to an axis's planes
            const Ray r(Vec3(u(rng), u(rng), u(rng)), glm::normalize(d));
            std::vector<double> ts{t(rng)};
            for (int a = 0; a < 3; ++a)
                if (r.d[a] != 0)
                    for (double p : L->planes(a)) {
                        const double c = r.tAt(a, p);
                        ts.insert(ts.end(), {c, std::nextafter(c, -kInf), std::nextafter(c, kInf)});
                    }
            for (double at : ts) {
                const std::optional<Cell> want = owner(r, at);
                inside += want.has_value();
                ASSERT_EQ(L->locate(r, at), want) << "ray " << i << " at t = " << at;
            }
        }
        EXPECT_GT(inside, 1000);  // (most of the cases are inside the lattice)
    }
}

// The face a ray leaves its box by (BoxSlabs::exitFace, what a node forwards
// it through after tracing it) is the first axis, x then y then z, along
// which the cell that owns the exit parameter lies beyond the box, and the
// way the ray moves along it; on the axes before it the owner is still in
// line with the box. Checked against Lattice::locate in a 3x3x3 lattice, for
// rays from inside the centre cell, including ties through edges and corners.
TEST(Dda, ExitFaceIsTheFirstAxisTheRayIsOutsideOf) {
    const Lattice L = Lattice::uniform(kBox, {3, 3, 3});
    const Box centre = L.cellBox({1, 1, 1});
    auto check = [&](const Ray& r) {
        const BoxSlabs b = boxSlabs(r, centre);
        const auto [axis, step] = b.exitFace(r);
        ASSERT_GE(axis, 0);
        ASSERT_EQ(step, r.d[axis] > 0 ? 1 : -1);
        const std::optional<Cell> owner = L.locate(r, b.span.hi);
        ASSERT_TRUE(owner.has_value());
        EXPECT_EQ((*owner)[axis], 1 + step) << "axis " << axis;
        for (int a = 0; a < axis; ++a) EXPECT_EQ((*owner)[a], 1) << "axis " << a << " before the exit axis " << axis;
    };
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> in(0.0, 1.0), dir(-1, 1);
    const Vec3 lo = centre.lo, size = centre.hi - centre.lo;
    for (int i = 0; i < 5000; ++i) {
        const Vec3 o = lo + Vec3(in(rng), in(rng), in(rng)) * size;
        Vec3 d(dir(rng), dir(rng), dir(rng));
        if (i % 5 == 0) d[i % 3] = 0;  // parallel to a face
        check(Ray(o, glm::normalize(d)));
    }
    // Through an edge and a corner from the cell's centre: ties go to the first axis.
    const Vec3 mid = lo + 0.5 * size;
    check(Ray(mid, glm::normalize(Vec3(1, 1, 0))));
    check(Ray(mid, glm::normalize(Vec3(0, -1, -1))));
    check(Ray(mid, glm::normalize(Vec3(-1, 1, -1))));
    EXPECT_EQ(boxSlabs(Ray(mid, glm::normalize(Vec3(0, -1, -1))), centre).exitFace(Ray(mid, glm::normalize(Vec3(0, -1, -1)))),
              std::make_pair(1, -1));
}
