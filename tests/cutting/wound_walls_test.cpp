// The walls that hang from an opened wound's lips: on every lip and only there, below the surface,
// facing into the gap and leaning toward the other lip.
#include <gtest/gtest.h>

#include "hapticut/cutting/progressive_cutter.h"
#include "hapticut/cutting/stroke_fuzzer.h"
#include "hapticut/cutting/wound_walls.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"

namespace hapticut::cutting {
namespace {

std::vector<Vec3> vertexNormals(std::span<const Vec3> x, std::span<const mesh::Face> faces) {
    std::vector<Vec3> n(x.size(), Vec3::Zero());
    for (const mesh::Face& f : faces) {
        const Vec3 area = (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]);
        for (std::uint32_t v : f) n[v] += area;
    }
    for (Vec3& v : n) v = v.norm() > 0 ? Vec3(v.normalized()) : Vec3::Zero();
    return n;
}

TEST(WoundWalls, HangFromBothLipsOfAnOpenedCutIntoTheOrganFacingTheGap) {
    const mesh::SurfaceMesh grid = mesh::procedural::makeGrid(10, 0.01);
    CutModel cut(grid, physics::buildModel(grid, physics::Material{}));
    ProgressiveCutter cutter(cut);
    // Left to right between the rows of vertices at y = 4.3 mm, stopping 2 cm short of the rims.
    constexpr double y0 = 0.0043;
    for (int i = 0; i <= 100; ++i) {
        const RestTouch t = touchRestSurface(cut, Vec3(-0.03 + 0.06 * i / 100.0, y0, 0));
        cutter.cutAt(t.face, t.bary);
    }
    cutter.endCut();
    ASSERT_TRUE(cutter.stats().opened);
    // Let the wound pull open.
    physics::Stepper stepper(physics::Scheme::RungeKutta4);
    stepper.prepare(cut.model());
    for (int i = 0; i < 400; ++i) stepper.step(cut.model(), 1e-3);

    const std::span<const Vec3> x = cut.model().nodes.position;
    const std::vector<Vec3> normals = vertexNormals(x, cut.mesh().faces);
    const Vec3 up = normals[0];  // the grid's outward side
    const std::vector<LipEdge> lips = lipEdges(cut.mesh().faces, rimEdges(grid.faces));
    ASSERT_GE(lips.size(), 2u * static_cast<std::size_t>(cutter.stats().cutPoints - 3));
    for (const LipEdge& e : lips)
        for (std::uint32_t v : {e.a, e.b}) {
            EXPECT_LT(std::abs(x[v].x()), 0.04) << "a rim of the grid is no lip";
            EXPECT_LT(std::abs(x[v].y() - y0), 0.006) << "lips lie along the cut";
        }
    EXPECT_TRUE(lipEdges(grid.faces, rimEdges(grid.faces)).empty());
    EXPECT_EQ(lipEdges(grid.faces).size(), rimEdges(grid.faces).size()) << "without rims, every boundary edge is a lip";

    WoundWalls walls;
    walls.setLips(lips);
    walls.update(x, normals);
    ASSERT_EQ(walls.faces().size(), 2 * lips.size());
    const std::size_t n = walls.lipVertices().size();
    ASSERT_EQ(walls.positions().size(), 2 * n);
    EXPECT_GT(walls.depth_m(), 0.003);
    EXPECT_LT(walls.depth_m(), 0.02);
    long leaning = 0, opened = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& lip = walls.positions()[i];
        const Vec3& foot = walls.positions()[n + i];
        EXPECT_EQ(lip, x[walls.lipVertices()[i]]);
        EXPECT_NEAR((lip - foot).dot(up), walls.depth_m(), 1e-9) << "the foot lies one depth under its lip";
        EXPECT_DOUBLE_EQ(walls.uvs()[i].y(), 0);
        EXPECT_DOUBLE_EQ(walls.uvs()[n + i].y(), 1);
        if (std::abs(lip.y() - y0) > 2e-4) {  // an opened lip, not a tip where the lips meet
            ++opened;
            leaning += std::abs(foot.y() - y0) < std::abs(lip.y() - y0);
        }
    }
    EXPECT_GT(opened, 6) << "the wound opened";
    EXPECT_EQ(leaning, opened) << "every foot leans toward the other lip";
    // Each wall faces into the gap: the lip above the cut line hangs a wall facing -y, the one below +y.
    for (const mesh::Face& f : walls.faces()) {
        const std::span<const Vec3> p = walls.positions();
        const Vec3 normal = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
        const double side = p[f[0]].y() + p[f[1]].y() -
                            2 * y0;  // which lip: f[0] and f[1] are wall vertices of one lip edge or its foot
        if (std::abs(side) < 4e-4 || normal.norm() < 1e-12) continue;  // at a tip
        EXPECT_LT(normal.y() * side, 0) << "a wall faces away from the gap";
    }
}

TEST(WoundWalls, AnUncutOrganHasNone) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    EXPECT_TRUE(lipEdges(heart.faces).empty());
    WoundWalls walls;
    walls.setLips({});
    walls.update(heart.positions, vertexNormals(heart.positions, heart.faces));
    EXPECT_TRUE(walls.empty());
    EXPECT_TRUE(walls.positions().empty());
}

}  // namespace
}  // namespace hapticut::cutting
