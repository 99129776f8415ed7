// Polygonising implicit shapes, and the procedural liver and kidney: segmented with slivers, then made
// simulation-ready (every part closed, outward, no angle under 25 degrees, near the shape and the count).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/implicit_surface.h"
#include "hapticut/mesh/procedural/organs.h"
#include "test_support.h"

namespace hapticut::mesh::procedural {
namespace {

constexpr double kRadius = 0.05;

SurfaceMesh sphereOfCell(double cell_m) {
    // Off the grid's symmetry, so the surface meets the cells in every way it can.
    const Vec3 centre(0.0031, -0.0017, 0.0023);
    return polygonise([&](const Vec3& p) { return (p - centre).norm() - kRadius; },
                      {Vec3::Constant(-0.06), Vec3::Constant(0.06)}, cell_m);
}

TEST(Polygonise, ASphereIsClosedOutwardAndConvergesAtSecondOrder) {
    double previousError = 0;
    for (const double cell : {0.008, 0.004, 0.002}) {
        SurfaceMesh sphere = sphereOfCell(cell);
        completeMesh(sphere);
        const MeshReport r = validateMesh(sphere);
        EXPECT_TRUE(r.closed && r.manifold && r.oriented) << "cell " << cell;
        EXPECT_EQ(r.components, 1u);
        EXPECT_EQ(r.eulerCharacteristic, 2) << "a sphere's topology";
        EXPECT_EQ(r.degenerateFaces, 0u);
        for (const Vec3& p : sphere.positions)
            EXPECT_NEAR((p - Vec3(0.0031, -0.0017, 0.0023)).norm(), kRadius, cell * cell / kRadius);
        // The inscribed surface's volume falls short of the ball's by O(cell^2).
        const double error =
            std::abs(test::signedVolume(sphere) / (4.0 / 3 * std::numbers::pi * std::pow(kRadius, 3)) - 1);
        EXPECT_GT(test::signedVolume(sphere), 0) << "faces point outward";
        if (previousError > 0) {
            EXPECT_GT(previousError / error, 3.5) << "halving the cell to " << cell;
        }
        previousError = error;
    }
}

// Like a user's segmentation: closed and outward, but with slivers no simulation wants; made ready, every
// part of it is even, closed and outward, at the count asked for, where the segmentation was.
void expectSegmentedThenReady(const SurfaceMesh& segmented, std::size_t triangles,
                              const std::vector<std::string>& parts) {
    SurfaceMesh raw = segmented;
    completeMesh(raw);
    const MeshReport before = validateMesh(raw);
    EXPECT_TRUE(before.closed && before.manifold && before.oriented);
    EXPECT_LT(before.minAngleDeg, 5) << "marching tetrahedra leave slivers";
    EXPECT_EQ(raw.partNames, parts);

    auto ready = makeSimulationReady(segmented, triangles);
    ASSERT_TRUE(ready.has_value()) << ready.error();
    const SurfaceMesh& organ = ready->mesh;
    const MeshReport after = validateMesh(organ);
    EXPECT_TRUE(after.closed && after.manifold && after.oriented);
    EXPECT_EQ(after.degenerateFaces, 0u);
    EXPECT_GE(after.minAngleDeg, 25);
    EXPECT_NEAR(static_cast<double>(after.faces), static_cast<double>(triangles),
                0.05 * static_cast<double>(triangles));
    EXPECT_LT(ready->remesh.distanceMax_m, 0.01 * (before.bboxMax - before.bboxMin).norm());
    // A clean segmentation is not smoothed first; its thin triangles the passes leave are mended.
    EXPECT_FALSE(ready->remesh.smoothedFirst);
    EXPECT_GT(ready->remesh.sliversMended, 0);
    EXPECT_EQ(organ.partNames, parts);
    for (std::uint32_t part = 0; part < parts.size(); ++part) {
        SurfaceMesh piece = organ;
        keepFaces(piece, [&](std::size_t f) { return piece.faceParts[f] == part; });
        completeMesh(piece);
        const MeshReport r = validateMesh(piece);
        EXPECT_TRUE(r.closed && r.oriented) << parts[part];
        EXPECT_EQ(r.components, 1u) << parts[part];
        EXPECT_GT(test::signedVolume(piece), 0) << parts[part] << " faces outward";
    }
}

TEST(Organs, TheKidneyIsSegmentedWithSliversAndMadeReady) {
    const SurfaceMesh kidney = segmentKidney();
    expectSegmentedThenReady(kidney, 3000, {"kidney", "adrenal gland"});
    const MeshReport r = validateMesh(kidney);
    const Vec3 size = r.bboxMax - r.bboxMin;
    EXPECT_NEAR(size.y(), 0.135, 0.005) << "11 cm of kidney, the gap and the adrenal gland";
    EXPECT_LT(size.z(), size.x()) << "flatter front to back than wide";
    EXPECT_LT(((r.bboxMax + r.bboxMin) / 2).norm(), 1e-12) << "centred";
}

TEST(Organs, TheLiverIsSegmentedWithSliversAndMadeReady) {
    const SurfaceMesh liver = segmentLiver(0.006);
    expectSegmentedThenReady(liver, 4000, {"liver", "gallbladder"});
    const MeshReport r = validateMesh(liver);
    EXPECT_NEAR(r.bboxMax.x() - r.bboxMin.x(), 0.245, 0.01) << "right lobe to the tip of the left";
}

}  // namespace
}  // namespace hapticut::mesh::procedural
