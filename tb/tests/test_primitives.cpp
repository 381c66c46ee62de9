// Ray-primitive intersections against analytic answers: inside/outside,
// tangent, behind the origin, one-sided back faces, intervals.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "shape.h"

using namespace rt;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

Shape make(std::variant<Sphere, Polygon, Cone> g, bool twoSided = false) {
    Shape s;
    s.geometry = std::move(g);
    s.twoSided = twoSided;
    return s;
}
double hit(const Shape& s, Vec3 o, Vec3 d, double lo = 0, double hi = kInf) {
    return s.intersect(Ray(o, glm::normalize(d)), lo, hi);
}
Polygon poly(std::vector<Vec3> v) {
    Polygon p;
    p.vertices = std::move(v);
    EXPECT_TRUE(p.finish());
    return p;
}
Cone cone(Vec3 b, double rb, Vec3 a, double ra, bool inside = false) {
    Cone c{b, rb, a, ra, inside, {}, 0, 0, {}};
    EXPECT_TRUE(c.finish());
    return c;
}
}  // namespace

TEST(Sphere, OutsideHitsNearSide) {
    const Shape s = make(Sphere{Vec3(0, 0, 0), 1, false});
    EXPECT_DOUBLE_EQ(hit(s, {0, 0, -5}, {0, 0, 1}), 4.0);
    EXPECT_NEAR(s.normal(Vec3(0, 0, -1)).z, -1.0, 1e-15);
}

TEST(Sphere, BehindOriginIsNoHit) {
    const Shape s = make(Sphere{Vec3(0, 0, 0), 1, false});
    EXPECT_EQ(hit(s, {0, 0, 5}, {0, 0, 1}), kInf);
}

TEST(Sphere, FromInsideOneSidedSeesNothingTwoSidedSeesFarSide) {
    EXPECT_EQ(hit(make(Sphere{Vec3(0), 1, false}), {0, 0, 0}, {1, 0, 0}), kInf);
    EXPECT_DOUBLE_EQ(hit(make(Sphere{Vec3(0), 1, false}, true), {0, 0, 0}, {1, 0, 0}), 1.0);
}

TEST(Sphere, InsideVisibleHitsOnlyTheInnerSurface) {
    const Shape s = make(Sphere{Vec3(0), 1, true});
    EXPECT_DOUBLE_EQ(hit(s, {0, 0, 0}, {1, 0, 0}), 1.0);
    EXPECT_DOUBLE_EQ(hit(s, {-5, 0, 0}, {1, 0, 0}), 6.0);  // near side is its back
    EXPECT_EQ(s.normal(Vec3(1, 0, 0)), Vec3(-1, 0, 0));
}

TEST(Sphere, TangentTouchesGrazingMisses) {
    const Shape s = make(Sphere{Vec3(0), 1, false});
    EXPECT_DOUBLE_EQ(hit(s, {1, 0, -5}, {0, 0, 1}), 5.0);
    EXPECT_EQ(hit(s, {1.000001, 0, -5}, {0, 0, 1}), kInf);
}

TEST(Sphere, IntervalIsHalfOpen) {
    const Shape s = make(Sphere{Vec3(0), 1, false});
    EXPECT_EQ(hit(s, {0, 0, -5}, {0, 0, 1}, 0, 4.0), kInf);   // t == hi excluded
    EXPECT_DOUBLE_EQ(hit(s, {0, 0, -5}, {0, 0, 1}, 4.0, 5.0), 4.0);  // t == lo included
}

TEST(Polygon, FrontFaceHitBackFaceCulled) {
    const Shape sq = make(poly({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}));  // CCW seen from +z
    EXPECT_DOUBLE_EQ(hit(sq, {0.2, 0.3, 5}, {0, 0, -1}), 5.0);
    EXPECT_EQ(hit(sq, {0.2, 0.3, -5}, {0, 0, 1}), kInf);  // one-sided: back face
    EXPECT_EQ(hit(sq, {1.5, 0.3, 5}, {0, 0, -1}), kInf);  // outside the outline
    EXPECT_EQ(hit(sq, {0, 0, 5}, {1, 0, 0}), kInf);       // parallel to the plane
    EXPECT_EQ(hit(sq, {0.2, 0.3, -5}, {0, 0, -1}), kInf); // plane behind the origin
    EXPECT_EQ(sq.normal(Vec3(0)), Vec3(0, 0, 1));
}

TEST(Polygon, TwoSidedHitsBothFaces) {
    const Shape sq = make(poly({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}), true);
    EXPECT_DOUBLE_EQ(hit(sq, {0.2, 0.3, -5}, {0, 0, 1}), 5.0);
}

TEST(Polygon, ConcaveOutlineAndReflexFirstCorner) {
    // An L shape whose first three vertices turn the "wrong" way (reflex
    // corner first): the Newell normal still gives the CCW side (+z).
    const Polygon L = poly({{1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}, {2, 1, 0}});
    EXPECT_EQ(L.n, Vec3(0, 0, 1));
    const Shape s = make(L);
    EXPECT_DOUBLE_EQ(hit(s, {0.5, 1.5, 1}, {0, 0, -1}), 1.0);  // in the upper arm
    EXPECT_DOUBLE_EQ(hit(s, {1.5, 0.5, 1}, {0, 0, -1}), 1.0);  // in the right arm
    EXPECT_EQ(hit(s, {1.5, 1.5, 1}, {0, 0, -1}), kInf);        // in the notch
}

TEST(Polygon, TiltedTriangle) {
    const Shape t = make(poly({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}));
    const double th = hit(t, {0, 0, 0}, {1, 1, 1});
    EXPECT_EQ(th, kInf);  // origin is behind the front face (normal points away from it)
    const double tf = hit(t, {1, 1, 1}, {-1, -1, -1});
    EXPECT_NEAR(tf, std::sqrt(3.0) - 1.0 / std::sqrt(3.0), 1e-15);
}

TEST(Cone, CylinderOutsideInsideAndEnds) {
    const Shape c = make(cone({0, 0, 0}, 1, {0, 0, 2}, 1));
    EXPECT_DOUBLE_EQ(hit(c, {-5, 0, 1}, {1, 0, 0}), 4.0);
    EXPECT_EQ(hit(c, {-5, 0, 2.5}, {1, 0, 0}), kInf);  // above the apex end, no cap
    EXPECT_EQ(hit(c, {0, 0, 1}, {1, 0, 0}), kInf);      // from inside, one-sided
    EXPECT_EQ(hit(c, {0, 0, -5}, {0, 0, 1}), kInf);     // along the axis through the open ends
    EXPECT_NEAR(glm::length(c.normal(Vec3(-1, 0, 1)) - Vec3(-1, 0, 0)), 0.0, 1e-15);
}

TEST(Cone, InsideVisibleCylinder) {
    const Shape c = make(cone({0, 0, 0}, 1, {0, 0, 2}, 1, true));
    EXPECT_DOUBLE_EQ(hit(c, {0, 0, 1}, {1, 0, 0}), 1.0);
    EXPECT_DOUBLE_EQ(hit(c, {-5, 0, 1}, {1, 0, 0}), 6.0);  // the near wall is seen from outside: its back
}

TEST(Cone, TrueConeHitAndNormal) {
    const Shape c = make(cone({0, 0, 0}, 1, {0, 0, 1}, 0));
    EXPECT_NEAR(hit(c, {-5, 0, 0.5}, {1, 0, 0}), 4.5, 1e-12);
    const Vec3 n = c.normal(Vec3(-0.5, 0, 0.5));
    EXPECT_NEAR(glm::length(n - glm::normalize(Vec3(-1, 0, 1))), 0.0, 1e-12);
    EXPECT_EQ(hit(c, {-5, 0, 1.5}, {1, 0, 0}), kInf);  // the mirrored nappe above the apex
}

TEST(Cone, TangentLine) {
    // A line touching the cylinder along x = 1 grazes it at one point.
    const Shape c = make(cone({0, 0, 0}, 1, {0, 0, 2}, 1));
    EXPECT_DOUBLE_EQ(hit(c, {1, -5, 1}, {0, 1, 0}), 5.0);
    EXPECT_EQ(hit(c, {1.0001, -5, 1}, {0, 1, 0}), kInf);
}

TEST(Bounds, ContainPrimitives) {
    EXPECT_EQ(make(Sphere{Vec3(1, 2, 3), 0.5, false}).bounds().lo, Vec3(0.5, 1.5, 2.5));
    const Box cb = make(cone({0, 0, 0}, 1, {0, 0, 2}, 0.5)).bounds();
    EXPECT_DOUBLE_EQ(cb.lo.x, -1);
    EXPECT_DOUBLE_EQ(cb.hi.y, 1);
    EXPECT_DOUBLE_EQ(cb.hi.z, 2);
}

#include "camera.h"

TEST(Camera, NffAngleIsBetweenOutermostPixelCentres) {
    View v;
    v.from = Vec3(1, 2, 3);
    v.at = Vec3(1, 2, -7);   // looking down -z
    v.up = Vec3(0, 3, 0.5);  // not unit, not orthogonal
    v.angle = 60;
    const Camera cam(v, 5, 3);
    const Ray centre = cam.primaryRay(2, 1);
    EXPECT_NEAR(glm::length(centre.d - Vec3(0, 0, -1)), 0.0, 1e-15);
    EXPECT_EQ(centre.o, v.from);
    // The outermost columns are 60 degrees apart, symmetric about the centre.
    const Ray left = cam.primaryRay(0, 1), right = cam.primaryRay(4, 1);
    EXPECT_NEAR(std::acos(glm::dot(left.d, right.d)) * 180 / M_PI, 60.0, 1e-9);
    EXPECT_LT(left.d.x, 0);
    EXPECT_GT(right.d.x, 0);
    // Square pixels: rows have the same spacing; row 0 is the top (+y here).
    const Ray top = cam.primaryRay(2, 0);
    EXPECT_GT(top.d.y, 0);
    EXPECT_NEAR(top.d.y / -top.d.z, std::tan(M_PI / 6) / 2, 1e-12);
}
