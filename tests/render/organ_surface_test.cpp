// Render vertices of the organ: one per (vertex, UV), smooth normals across seams, lips flagged.
#include <gtest/gtest.h>

#include "hapticut/cutting/cut_model.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/physics/material.h"
#include "render/organ_surface.h"
#include "render/vertex_layout.h"

namespace hapticut::render {
namespace {

TEST(OrganSurface, SeamVerticesSplitForUvsButShareOneNormal) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    OrganSurface s;
    s.setTopology(heart.faces, heart.uvs, {}, heart.positions.size());
    s.update(heart.positions);
    // The spherical UVs have a seam: more render vertices than vertices, fewer than corners.
    EXPECT_GT(s.renderVertexCount(), heart.positions.size());
    EXPECT_LT(s.renderVertexCount(), heart.faces.size() * 3);
    ASSERT_EQ(s.vertices().size(), s.renderVertexCount() * kFloatsPerVertex);
    const auto v = s.vertices();
    for (std::size_t i = 0; i < s.indices().size(); ++i) {
        const std::uint32_t r = s.indices()[i];
        const std::uint32_t vertex = heart.faces[i / 3][i % 3];
        const Vec3 normal(v[r * kFloatsPerVertex + 3], v[r * kFloatsPerVertex + 4], v[r * kFloatsPerVertex + 5]);
        // Every render vertex of a model vertex carries that vertex's one normal, seam or not.
        ASSERT_TRUE(normal.isApprox(s.vertexNormal(vertex).cast<float>().cast<double>(), 1e-6)) << "corner " << i;
        EXPECT_FLOAT_EQ(v[r * kFloatsPerVertex + 6], static_cast<float>(heart.uvs[i / 3][i % 3].x()));
        EXPECT_EQ(v[r * kFloatsPerVertex + 8], 0.0f);  // a closed heart has no lips
    }
}

TEST(OrganSurface, NormalsOfASpherePointOutward) {
    const mesh::SurfaceMesh sphere = mesh::procedural::makeSphere(Vec3(0.1, 0, 0), 0.05, 24, 12);
    OrganSurface s;
    s.setTopology(sphere.faces, sphere.uvs, {}, sphere.positions.size());
    s.update(sphere.positions);
    for (std::size_t i = 0; i < sphere.positions.size(); ++i)
        EXPECT_GT(s.vertexNormal(i).dot((sphere.positions[i] - Vec3(0.1, 0, 0)).normalized()), 0.97) << "vertex " << i;
}

TEST(OrganSurface, AnOpeningWithoutWallsHasItsLipsFlaggedButNotTheOrgansOwnRim) {
    mesh::SurfaceMesh grid = mesh::procedural::makeGrid(8, 0.01);
    cutting::CutModel organ(grid, physics::buildModel(grid, physics::Material{}));
    // A straight cut along the grid's middle row of vertices (n = 8: 9 x 9 vertices, row 4).
    const std::uint32_t row = 4 * 9;
    const std::uint32_t a = row + 2, b = row + 3, c = row + 4;
    const auto copy = organ.openCut(a, b, c);
    ASSERT_TRUE(copy);
    OrganSurface s;
    s.setTopology(organ.mesh().faces, organ.mesh().uvs, organ.wallFaces(), organ.mesh().positions.size());
    s.update(organ.model().nodes.position);
    EXPECT_TRUE(s.onLip(b));
    EXPECT_TRUE(s.onLip(*copy));
    EXPECT_FALSE(s.onLip(row - 9 * 2 + 4));  // two rows away, inside the grid
    // Without the uncut organ's faces, the grid's own open rim counts as a lip too.
    EXPECT_TRUE(s.onLip(0));
    OrganSurface told;
    told.setRims(grid.faces);
    told.setTopology(organ.mesh().faces, organ.mesh().uvs, organ.wallFaces(), organ.mesh().positions.size());
    EXPECT_FALSE(told.onLip(0));
    EXPECT_TRUE(told.onLip(b));
}

TEST(OrganSurface, AWoundsWallsAreDrawnInTheirOwnMaterialWithNormalsOfTheirOwn) {
    mesh::SurfaceMesh grid = mesh::procedural::makeGrid(8, 0.01);
    cutting::CutModel organ(grid, physics::buildModel(grid, physics::Material{}));
    const std::uint32_t row = 4 * 9;
    const std::uint32_t a = row + 2, b = row + 3, c = row + 4;
    const auto copy = organ.openCut(a, b, c, 0.1, 0.3);
    ASSERT_TRUE(copy);
    ASSERT_TRUE(organ.closeOpening(b, *copy, 0.01));
    OrganSurface s;
    s.setRims(grid.faces);
    s.setTopology(organ.mesh().faces, organ.mesh().uvs, organ.wallFaces(), organ.mesh().positions.size());
    s.update(organ.model().nodes.position);
    // Every face is drawn; the four walls' corners are render vertices of the wall's own (wound
    // attribute 2), and the lips, where the surface meets the walls, are flagged.
    ASSERT_EQ(s.indices().size(), 3 * organ.mesh().faces.size());
    const auto v = s.vertices();
    int wallCorners = 0;
    for (std::size_t i = 0; i < s.indices().size(); ++i) {
        const std::uint32_t r = s.indices()[i];
        const bool wall = organ.isWall(static_cast<std::uint32_t>(i / 3));
        EXPECT_EQ(v[r * kFloatsPerVertex + 8] == 2.0f, wall) << "corner " << i;
        wallCorners += wall;
    }
    EXPECT_EQ(wallCorners, 12);
    for (std::uint32_t lip : {a, b, *copy, c}) EXPECT_TRUE(s.onLip(lip)) << lip;
    EXPECT_FALSE(s.onLip(0));
    // The surface normal at the lip b points out of the grid (+z), whatever the wall below it does.
    EXPECT_GT(s.vertexNormal(b).z(), 0.9);

    OrganSurface hidden;
    hidden.setWallsShown(false);
    hidden.setTopology(organ.mesh().faces, organ.mesh().uvs, organ.wallFaces(), organ.mesh().positions.size());
    EXPECT_EQ(hidden.indices().size(), 3 * (organ.mesh().faces.size() - 4));
}

}  // namespace
}  // namespace hapticut::render
