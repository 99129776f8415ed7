// Adjacency and the validation report on meshes whose answers are known by hand.
#include <gtest/gtest.h>

#include "hapticut/mesh/adjacency.h"
#include "hapticut/mesh/edge_flip.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "test_support.h"

namespace hapticut::mesh {
namespace {

TEST(MeshReport, ClosedTetrahedron) {
    const MeshReport r = validateMesh(test::tetrahedron());
    EXPECT_EQ(r.vertices, 4u);
    EXPECT_EQ(r.faces, 4u);
    EXPECT_EQ(r.edges, 6u);
    EXPECT_EQ(r.boundaryEdges, 0u);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.manifold);
    EXPECT_TRUE(r.oriented);
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(r.eulerCharacteristic, 2);
    EXPECT_NEAR(r.minAngleDeg, 60, 1e-9);
    EXPECT_GT(test::signedVolume(test::tetrahedron()), 0);
}

TEST(MeshReport, OpenGridHasItsRimAsBoundary) {
    const MeshReport r = validateMesh(procedural::makeGrid(4, 0.01));
    EXPECT_EQ(r.boundaryEdges, 16u);
    EXPECT_FALSE(r.closed);
    EXPECT_TRUE(r.manifold);
    EXPECT_TRUE(r.oriented);
    EXPECT_EQ(r.eulerCharacteristic, 1);
    EXPECT_NEAR(r.area_m2, 0.04 * 0.04, 1e-15);
}

TEST(MeshReport, FlippedFaceBreaksOrientation) {
    SurfaceMesh m = test::tetrahedron();
    std::swap(m.faces[2][1], m.faces[2][2]);
    const MeshReport r = validateMesh(m);
    EXPECT_TRUE(r.manifold);
    EXPECT_FALSE(r.oriented);
    EXPECT_EQ(r.misorientedEdges, 3u);
}

TEST(MeshReport, ThirdFaceOnAnEdgeIsNonManifold) {
    SurfaceMesh m = test::tetrahedron();
    m.positions.push_back(Vec3(3, 3, 3));
    m.faces.push_back({0, 1, 4});
    completeMesh(m);
    m.edges = edgesOfFaces(m.faces);
    const MeshReport r = validateMesh(m);
    EXPECT_EQ(r.nonManifoldEdges, 1u);
    EXPECT_FALSE(r.manifold);
    EXPECT_FALSE(r.oriented);
}

TEST(MeshReport, CountsComponentsAndSpringMismatches) {
    SurfaceMesh m = test::tetrahedron();
    procedural::appendMesh(m, test::tetrahedron());
    m.edges.pop_back();
    m.edges.push_back({0, 7});
    const MeshReport r = validateMesh(m);
    EXPECT_EQ(r.components, 2u);
    EXPECT_EQ(r.eulerCharacteristic, 4);
    EXPECT_EQ(r.springsNotOnFaces, 1u);
    EXPECT_EQ(r.faceEdgesWithoutSpring, 1u);
}

TEST(Adjacency, NeighboursAreMutualAndEdgesKnowTheirFaces) {
    const SurfaceMesh grid = procedural::makeGrid(5, 0.01);
    const MeshAdjacency adj = buildAdjacency(grid.faces);
    std::size_t boundary = 0;
    for (std::uint32_t f = 0; f < grid.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t g = adj.faceNeighbours[f][k];
            const Edge& e = adj.edges[adj.faceEdges[f][k]];
            const std::uint32_t a = grid.faces[f][k], b = grid.faces[f][(k + 1) % 3];
            EXPECT_EQ(e, (Edge{std::min(a, b), std::max(a, b)}));
            if (g == kNoFace) {
                ++boundary;
                continue;
            }
            bool back = false;
            for (int j = 0; j < 3; ++j) back |= adj.faceNeighbours[g][j] == f;
            EXPECT_TRUE(back);
        }
    EXPECT_EQ(boundary, 20u);
}

TEST(EdgeFlip, RaisesTheMinimumAngleAndKeepsTheSurfaceValid) {
    // A grid with one vertex pulled sideways has thin triangles that flips can improve.
    SurfaceMesh grid = procedural::makeGrid(6, 0.01);
    grid.positions[3 * 7 + 3].x() += 0.0045;
    const double before = validateMesh(grid).minAngleDeg;
    EXPECT_GT(improveByEdgeFlips(grid), 0);
    const MeshReport after = validateMesh(grid);
    EXPECT_GT(after.minAngleDeg, before);
    EXPECT_EQ(after.faces, 72u);
    EXPECT_TRUE(after.manifold);
    EXPECT_TRUE(after.oriented);
    EXPECT_EQ(after.boundaryEdges, 24u);
    EXPECT_EQ(after.springs, after.edges);
}

}  // namespace
}  // namespace hapticut::mesh
