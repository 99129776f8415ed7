// Triangle queries against brute force and hand values: the closest point on a triangle is no farther
// than any sampled point of it and its barycentrics rebuild it; segment hits from both sides; areas,
// normals and angles of known triangles; bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hapticut/geometry/aabb.h"
#include "hapticut/geometry/triangle.h"
#include "hapticut/geometry/triangle_queries.h"
#include "test_support.h"

namespace hapticut::geometry {
namespace {

TEST(ClosestPointOnTriangle, IsNoFartherThanAnyPointOfTheTriangleAndItsBarycentricsRebuildIt) {
    const Vec3 a(0.01, -0.02, 0.003), b(0.05, 0.01, -0.01), c(-0.02, 0.04, 0.02);
    for (std::size_t i = 0; i < 300; ++i) {
        const Vec3 p = test::wobble(i, 0.08);  // in every Voronoi region of the triangle
        const ClosestOnTriangle q = closestPointOnTriangle(p, a, b, c);
        EXPECT_NEAR(q.bary.sum(), 1, 1e-12);
        EXPECT_GE(q.bary.minCoeff(), -1e-12);
        EXPECT_LT((q.bary.x() * a + q.bary.y() * b + q.bary.z() * c - q.point).norm(), 1e-12);
        const double d = (p - q.point).norm();
        for (int u = 0; u <= 20; ++u)
            for (int v = 0; u + v <= 20; ++v) {
                const Vec3 s = a + (u / 20.0) * (b - a) + (v / 20.0) * (c - a);
                ASSERT_LE(d, (p - s).norm() + 1e-12) << "sample point " << u << "," << v << " is closer, p " << i;
            }
    }
}

TEST(IntersectSegmentTriangle, HitsFromBothSidesWithTheRightFractionAndMissesBeside) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    const auto down = intersectSegmentTriangle(Vec3(0.2, 0.3, 1), Vec3(0.2, 0.3, -3), a, b, c);
    ASSERT_TRUE(down);
    EXPECT_NEAR(down->t, 0.25, 1e-12);
    EXPECT_TRUE(down->bary.isApprox(Vec3(0.5, 0.2, 0.3), 1e-12));
    const auto up = intersectSegmentTriangle(Vec3(0.2, 0.3, -1), Vec3(0.2, 0.3, 1), a, b, c);
    ASSERT_TRUE(up) << "back faces count (R10)";
    EXPECT_NEAR(up->t, 0.5, 1e-12);
    EXPECT_FALSE(intersectSegmentTriangle(Vec3(0.8, 0.8, 1), Vec3(0.8, 0.8, -1), a, b, c)) << "beside the hypotenuse";
    EXPECT_FALSE(intersectSegmentTriangle(Vec3(0.2, 0.3, 1), Vec3(0.2, 0.3, 0.5), a, b, c)) << "stops short";
    EXPECT_TRUE(intersectSegmentTriangle(Vec3(0.5, 0.5, 1), Vec3(0.5, 0.5, -1), a, b, c)) << "an edge counts as inside";
}

TEST(Triangle, AreaNormalAndSmallestAngleOfKnownTriangles) {
    const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 1, 0);
    EXPECT_DOUBLE_EQ(triangleArea(a, b, c), 1.0);
    EXPECT_TRUE(unitNormal(a, b, c).isApprox(Vec3(0, 0, 1)));
    EXPECT_NEAR(minAngle(a, b, c), std::atan(0.5), 1e-12);
    const double s = std::sqrt(3.0) / 2;
    EXPECT_NEAR(minAngle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, s, 0)), std::numbers::pi / 3, 1e-12);
    EXPECT_EQ(unitNormal(a, b, 2 * b), Vec3::Zero()) << "degenerate";
    EXPECT_EQ(minAngle(a, b, 2 * b), 0);
}

TEST(Aabb, BoundsHoldEveryPointAndStartEmpty) {
    EXPECT_TRUE(Aabb{}.empty());
    const std::vector<Vec3> points{Vec3(1, -2, 3), Vec3(-1, 4, 0), Vec3(0, 0, -5)};
    const Aabb box = boundsOf(points);
    EXPECT_FALSE(box.empty());
    EXPECT_EQ(box.min, Vec3(-1, -2, -5));
    EXPECT_EQ(box.max, Vec3(1, 4, 3));
    EXPECT_EQ(box.center(), Vec3(0, 1, -1));
    EXPECT_EQ(box.extent(), Vec3(2, 6, 8));
}

}  // namespace
}  // namespace hapticut::geometry
