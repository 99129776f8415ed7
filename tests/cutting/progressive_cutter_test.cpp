// Scalpel strokes through the progressive cutter: a straight stroke (the thesis's figure 3.6), strokes
// through vertices, a fast stroke, and many random strokes on the heart with every invariant kept.
#include <gtest/gtest.h>

#include <random>

#include "hapticut/cutting/invariants.h"
#include "hapticut/cutting/progressive_cutter.h"
#include "hapticut/cutting/stroke_fuzzer.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"

namespace hapticut::cutting {
namespace {

CutModel cuttable(const mesh::SurfaceMesh& mesh) { return CutModel(mesh, physics::buildModel(mesh, physics::Material{})); }

/// Where the scalpel touches: the rest surface's closest face and barycentrics.
std::pair<std::uint32_t, Vec3> touch(const CutModel& cut, const Vec3& p) {
    const RestTouch t = touchRestSurface(cut, p);
    return {t.face, t.bary};
}

/// The closest point of the rest surface to p.
Vec3 touchPoint(const CutModel& cut, const Vec3& p) { return touchRestSurface(cut, p).point; }

void stroke(CutModel& cut, ProgressiveCutter& cutter, const Vec3& from, const Vec3& to, int samples) {
    for (int i = 0; i <= samples; ++i) {
        const auto [face, bary] = touch(cut, from + (to - from) * (static_cast<double>(i) / samples));
        cutter.cutAt(face, bary);
    }
    cutter.endCut();
}

TEST(ProgressiveCutter, AStraightStrokeOpensAWoundAlongItsPath) {
    // 10 x 10 grid of 1 cm cells; the stroke runs left to right between the rows of vertices.
    CutModel cut = cuttable(mesh::procedural::makeGrid(10, 0.01));
    const double mass = physics::totalMass(cut.model());
    ProgressiveCutter cutter(cut);
    const std::size_t boundary0 = mesh::validateMesh(cut.mesh()).boundaryEdges;
    stroke(cut, cutter, Vec3(-0.032, 0.0043, 0), Vec3(0.028, 0.0043, 0), 120);
    const CutStats& s = cutter.stats();
    EXPECT_EQ(s.cuts, 1);
    EXPECT_TRUE(s.opened);
    EXPECT_GT(s.cutPoints, 10) << "a point in the first face and one per crossed edge";
    EXPECT_NEAR(s.length_m, 0.06, 0.01);
    const InvariantReport r = checkInvariants(cut, mass);
    ASSERT_TRUE(r.ok()) << r.problems.front();
    const mesh::MeshReport after = mesh::validateMesh(cut.mesh());
    // Every cut edge but the two at the ends (the wound tapers shut there) appears twice as boundary.
    EXPECT_GE(after.boundaryEdges, boundary0 + 2 * static_cast<std::size_t>(s.cutPoints - 3));
    // Every cut point lies on the stroke's line (rest shape): the cut follows the scalpel.
    for (std::uint32_t v : cutter.points()) EXPECT_NEAR(cut.mesh().positions[v].y(), 0.0043, 0.0015);
    EXPECT_TRUE(after.manifold);
    EXPECT_TRUE(after.oriented);
}

TEST(ProgressiveCutter, AStrokeThroughVerticesSnapsInsteadOfMakingSlivers) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(10, 0.01));
    const std::size_t vertices0 = cut.mesh().positions.size();
    ProgressiveCutter cutter(cut);
    // Along the grid line y = 0 and exactly through its vertices: every crossing lands on a vertex.
    stroke(cut, cutter, Vec3(-0.03, 0.0, 0), Vec3(0.03, 0.0, 0), 60);
    const InvariantReport r = checkInvariants(cut, physics::totalMass(cut.model()));
    ASSERT_TRUE(r.ok()) << r.problems.front();
    EXPECT_GE(cutter.stats().cutPoints, 6);
    // Only the duplicates of opened points were added: no edge or face splits.
    EXPECT_EQ(cut.mesh().positions.size() - vertices0, static_cast<std::size_t>(cutter.stats().cutPoints - 2));
    EXPECT_GT(mesh::validateMesh(cut.mesh()).minAngleDeg, 20.0);
}

TEST(ProgressiveCutter, AFastStrokeCutsEveryFaceOnItsWayInOrder) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(10, 0.01));
    ProgressiveCutter cutter(cut);
    // Two samples: the start, then 6 cm further in one step.
    const std::vector<std::uint32_t> points = [&] {
        for (const Vec3& p : {Vec3(-0.031, -0.0027, 0), Vec3(0.029, -0.0027, 0)}) {
            const auto [face, bary] = touch(cut, p);
            cutter.cutAt(face, bary);
        }
        return cutter.points();
    }();
    cutter.endCut();
    ASSERT_GE(points.size(), 6u) << "one call crossed every face to the far end";
    // In order along the stroke, and reaching its end.
    for (std::size_t i = 1; i < points.size(); ++i) EXPECT_GT(cut.mesh().positions[points[i]].x(), cut.mesh().positions[points[i - 1]].x());
    EXPECT_NEAR(cut.mesh().positions[points.back()].x(), 0.029, 0.01);
    const InvariantReport r = checkInvariants(cut, physics::totalMass(cut.model()));
    ASSERT_TRUE(r.ok()) << r.problems.front();
    EXPECT_NEAR(cutter.stats().length_m, 0.06, 0.01);
}

TEST(ProgressiveCutter, RandomStrokesOnTheHeartKeepEveryInvariant) {
    std::mt19937 rng(3);
    CutModel cut = cuttable(mesh::procedural::makeHeart({}));
    const double mass = physics::totalMass(cut.model());
    ProgressiveCutter cutter(cut);
    std::uniform_real_distribution<double> unit(-1, 1), length(0.005, 0.03);
    for (int i = 0; i < 150; ++i) {
        // Start on the surface at a random place, stroke in a random tangent direction.
        const Vec3 start = touchPoint(cut, Vec3(unit(rng), unit(rng), unit(rng)).normalized() * 0.1);
        const Vec3 dir = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
        const Vec3 end = touchPoint(cut, start + length(rng) * dir);
        stroke(cut, cutter, start, end, 1 + static_cast<int>(rng() % 30));
        const InvariantReport r = checkInvariants(cut, mass);
        ASSERT_TRUE(r.ok()) << "after stroke " << i << ": " << r.problems.front();
    }
    EXPECT_GT(cutter.stats().cutPoints, 500);
    EXPECT_TRUE(cutter.stats().opened);
    physics::Stepper stepper(physics::Scheme::RungeKutta4);
    stepper.setAutoSubstep(false);
    stepper.prepare(cut.model());
    for (int i = 0; i < 100; ++i) ASSERT_TRUE(stepper.step(cut.model(), stepper.stableStep_s()).finite);
}

}  // namespace
}  // namespace hapticut::cutting
