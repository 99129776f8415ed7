// The procedural heart and tools: closed, manifold, outward, well shaped, sized and placed as documented.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/tools.h"
#include "test_support.h"

namespace hapticut::mesh::procedural {
namespace {

void expectGoodHeart(int triangles, double min_angle_deg) {
    HeartOptions options;
    options.triangles = triangles;
    const SurfaceMesh heart = makeHeart(options);
    const MeshReport r = validateMesh(heart);
    EXPECT_NEAR(static_cast<double>(r.faces), triangles, 0.02 * triangles);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.manifold);
    EXPECT_TRUE(r.oriented);
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(r.eulerCharacteristic, 2);
    EXPECT_EQ(r.degenerateFaces, 0u);
    EXPECT_EQ(r.springs, r.edges);
    EXPECT_EQ(r.springsNotOnFaces, 0u);
    EXPECT_GT(r.minAngleDeg, min_angle_deg);
    EXPECT_GT(test::signedVolume(heart), 0) << "faces must point outward";
    // 0.12 m long along y, bounding box centred at the origin.
    EXPECT_NEAR(r.bboxMax.y() - r.bboxMin.y(), 0.12, 1e-12);
    EXPECT_LT(((r.bboxMax + r.bboxMin) / 2).norm(), 1e-12);
    // Not a sphere: narrower than long, and shallower front to back than wide.
    EXPECT_LT(r.bboxMax.x() - r.bboxMin.x(), 0.8 * 0.12);
    EXPECT_LT(r.bboxMax.z() - r.bboxMin.z(), r.bboxMax.x() - r.bboxMin.x());
    ASSERT_EQ(heart.uvs.size(), heart.faces.size());
    for (const FaceUvs& uv : heart.uvs)
        for (const Vec2& t : uv) {
            EXPECT_TRUE(t.allFinite());
            EXPECT_GE(t.y(), 0);
            EXPECT_LE(t.y(), 1);
        }
}

TEST(ProceduralHeart, ThesisSize1619) { expectGoodHeart(1619, 20); }
TEST(ProceduralHeart, Size9714) { expectGoodHeart(9714, 20); }
TEST(ProceduralHeart, Size100k) { expectGoodHeart(100'000, 15); }
TEST(ProceduralHeart, Size1M) { expectGoodHeart(1'000'000, 15); }

TEST(ProceduralHeart, ApexPointsDownAndGreatVesselsUp) {
    const SurfaceMesh heart = makeHeart({});
    // The apex is the lowest point and lies left (+x) and forward of the vessels at the top.
    Vec3 low = heart.positions[0], high = heart.positions[0];
    for (const Vec3& p : heart.positions) {
        if (p.y() < low.y()) low = p;
        if (p.y() > high.y()) high = p;
    }
    EXPECT_GT(low.x(), high.x());
    EXPECT_NEAR(low.y(), -0.06, 1e-12);
}

TEST(ProceduralHeart, UvsAreContinuousInsideEachFace) {
    // A face on the texture seam takes u past 1 rather than spanning the whole texture. Spherical UVs
    // are singular at the apex and the top (v = 0 and 1), where a face around the pole spans any u, so
    // those faces are left out; elsewhere a face covers only a small patch of the texture.
    const SurfaceMesh heart = makeHeart({});
    for (const FaceUvs& uv : heart.uvs)
        for (int k = 0; k < 3; ++k) {
            const bool nearPole =
                std::min({uv[0].y(), uv[1].y(), uv[2].y()}) < 0.1 || std::max({uv[0].y(), uv[1].y(), uv[2].y()}) > 0.9;
            if (!nearPole) {
                EXPECT_LT(std::abs(uv[k].x() - uv[(k + 1) % 3].x()), 0.5);
            }
            if (std::abs(uv[k].y() - 0.5) < 0.35) {
                EXPECT_LT((uv[k] - uv[(k + 1) % 3]).norm(), 0.1);
            }
        }
}

TEST(ProceduralTools, ScalpelAndProbeAreClosedOutwardAndTipAtOrigin) {
    for (const SurfaceMesh& tool : {makeScalpel(), makeProbe()}) {
        const MeshReport r = validateMesh(tool);
        EXPECT_TRUE(r.closed);
        EXPECT_TRUE(r.manifold);
        EXPECT_TRUE(r.oriented);
        EXPECT_EQ(r.components, 2u);
        EXPECT_GT(test::signedVolume(tool), 0);
        EXPECT_NEAR(r.bboxMin.z(), 0, 1e-12) << "the interaction point is the tip, at the origin";
        EXPECT_GT(r.bboxMax.z(), 0.1) << "the handle runs along +z";
    }
    EXPECT_LT(kScalpelThreshold_N, 3.3);
}

}  // namespace
}  // namespace hapticut::mesh::procedural
