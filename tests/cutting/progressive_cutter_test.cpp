// Scalpel strokes through the progressive cutter: a straight stroke (the thesis's figure 3.6), strokes
// through vertices, a fast stroke, and many random strokes on the heart with every invariant kept.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "cutting/cuttable.h"
#include "hapticut/cutting/invariants.h"
#include "hapticut/cutting/progressive_cutter.h"
#include "hapticut/cutting/stroke_fuzzer.h"
#include "hapticut/geometry/random_vec.h"
#include "hapticut/geometry/triangle.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/physics/integrators.h"

namespace hapticut::cutting {
namespace {

using test::cuttable;

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

TEST(ProgressiveCutter, AStraightStrokeOpensAWoundAlongItsPathClosedByWallsBelowIt) {
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
    // Every opened point (all but the two at the ends) gapes, and walls close the gap: the surface has
    // no new boundary, and under each opened point a floor vertex lies about one of the cut's edge
    // lengths (3 to 7 mm here) deep, below the grid (whose outside is +z), midway between the lips.
    EXPECT_EQ(s.wallsClosed, s.cutPoints - 2);
    EXPECT_EQ(after.boundaryEdges, boundary0);
    int floors = 0;
    for (std::uint32_t v = 0; v < cut.mesh().positions.size(); ++v) {
        const auto floor = cut.floorUnder(v);
        if (!floor) continue;
        ++floors;
        const Vec3& q = cut.mesh().positions[*floor];
        EXPECT_LT(q.z(), -0.002);
        EXPECT_GT(q.z(), -0.012);
        EXPECT_NEAR(q.y(), 0.0043, 0.0015);
    }
    EXPECT_EQ(floors, 2 * s.wallsClosed) << "both lips of an opening share its floor";
    // Every cut point lies on the stroke's line (rest shape): the cut follows the scalpel.
    for (std::uint32_t v : cutter.points()) EXPECT_NEAR(cut.mesh().positions[v].y(), 0.0043, 0.0015);
    EXPECT_TRUE(after.manifold);
    EXPECT_TRUE(after.oriented);
}

TEST(ProgressiveCutter, WithoutWallsTheWoundIsAnOpeningInTheSurface) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(10, 0.01));
    const double mass = physics::totalMass(cut.model());
    ProgressiveCutter cutter(cut, CutterParams{.walls = false});
    const std::size_t boundary0 = mesh::validateMesh(cut.mesh()).boundaryEdges;
    stroke(cut, cutter, Vec3(-0.032, 0.0043, 0), Vec3(0.028, 0.0043, 0), 120);
    const CutStats& s = cutter.stats();
    const InvariantReport r = checkInvariants(cut, mass);
    ASSERT_TRUE(r.ok()) << r.problems.front();
    const mesh::MeshReport after = mesh::validateMesh(cut.mesh());
    // Every cut edge but the two at the ends (the wound tapers shut there) appears twice as boundary.
    EXPECT_EQ(s.wallsClosed, 0);
    EXPECT_GE(after.boundaryEdges, boundary0 + 2 * static_cast<std::size_t>(s.cutPoints - 3));
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
    // Only the duplicates of opened points and their floors were added: no edge or face splits.
    EXPECT_EQ(cutter.stats().wallsClosed, cutter.stats().cutPoints - 2);
    EXPECT_EQ(cut.mesh().positions.size() - vertices0, static_cast<std::size_t>(2 * (cutter.stats().cutPoints - 2)));
    EXPECT_GT(mesh::validateMesh(cut.mesh()).minAngleDeg, 15.0);
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
    for (std::size_t i = 1; i < points.size(); ++i)
        EXPECT_GT(cut.mesh().positions[points[i]].x(), cut.mesh().positions[points[i - 1]].x());
    EXPECT_NEAR(cut.mesh().positions[points.back()].x(), 0.029, 0.01);
    const InvariantReport r = checkInvariants(cut, physics::totalMass(cut.model()));
    ASSERT_TRUE(r.ok()) << r.problems.front();
    EXPECT_NEAR(cutter.stats().length_m, 0.06, 0.01);
}

/// Groups of vertices joined by edges: of the faces (pieces), or of the boundary edges only (openings).
int countGroups(const mesh::SurfaceMesh& m, bool boundaryOnly) {
    std::vector<std::uint32_t> parent(m.positions.size());
    for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
    auto root = [&](std::uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const mesh::Face& f : m.faces)
        for (int k = 0; k < 3; ++k) ++uses[std::minmax(f[k], f[(k + 1) % 3])];
    std::vector<char> used(m.positions.size(), 0);
    for (const auto& [edge, count] : uses) {
        if (boundaryOnly && count != 1) continue;
        parent[root(edge.first)] = root(edge.second);
        used[edge.first] = used[edge.second] = 1;
    }
    int groups = 0;
    for (std::uint32_t v = 0; v < parent.size(); ++v) groups += used[v] && root(v) == v;
    return groups;
}

TEST(ProgressiveCutter, ACutAcrossTheWholeGridJoinsBothRimsAndLeavesTwoPiecesThatBothSimulate) {
    const mesh::SurfaceMesh grid = mesh::procedural::makeGrid(10, 0.01);
    CutModel cut = cuttable(grid);
    const double mass = physics::totalMass(cut.model());
    ProgressiveCutter cutter(cut);
    ASSERT_EQ(countGroups(cut.mesh(), false), 1);
    // From the left rim's vertex row... no: between rows, from just inside the left rim to past the right.
    const Vec3 from(-0.0495, 0.0043, 0), to(0.06, 0.0043, 0);
    for (int i = 0; i <= 200; ++i) {
        const RestTouch t = touchRestSurface(cut, from + (to - from) * (i / 200.0));
        cutter.cutAt(t.face, t.bary);
    }
    cutter.endCut();
    const InvariantReport r = checkInvariants(cut, mass);
    ASSERT_TRUE(r.ok()) << r.problems.front();
    EXPECT_GE(cutter.stats().joins, 1) << "the cut ran into the right rim and joined it";
    EXPECT_EQ(countGroups(cut.mesh(), false), 2) << "the cut separates the grid into two pieces";
    EXPECT_EQ(countGroups(cut.mesh(), true), 2) << "each piece has its own rim";

    // Each piece simulates on its own: pull one node of each, the piece it belongs to follows and the
    // other does not feel it, and nothing goes non-finite.
    physics::MassSpringModel& model = cut.model();
    physics::Stepper stepper(physics::Scheme::RungeKutta4);
    stepper.prepare(model);
    for (int i = 0; i < 300; ++i) ASSERT_TRUE(stepper.step(model, 1e-3).finite);
    const std::vector<Vec3> settled = model.nodes.position;
    auto nearest = [&](const Vec3& p) {
        std::uint32_t best = 0;
        for (std::uint32_t v = 1; v < model.nodes.size(); ++v)
            if ((cut.mesh().positions[v] - p).norm() < (cut.mesh().positions[best] - p).norm()) best = v;
        return best;
    };
    for (const double y : {0.03, -0.03}) {
        const std::uint32_t pulled = nearest(Vec3(0, y, 0));
        model.nodes.position = settled;
        std::fill(model.nodes.velocity.begin(), model.nodes.velocity.end(), Vec3::Zero());
        model.nodes.externalForce[pulled] = Vec3(0, 0, 0.5);
        stepper.wake(pulled);
        for (int i = 0; i < 100; ++i) ASSERT_TRUE(stepper.step(model, 1e-3).finite);
        model.nodes.externalForce[pulled] = Vec3::Zero();
        double sameSide = 0, otherSide = 0;
        for (std::uint32_t v = 0; v < model.nodes.size(); ++v) {
            const double lift = std::abs(model.nodes.position[v].z() - settled[v].z());
            ((cut.mesh().positions[v].y() - 0.0043) * y > 0 ? sameSide : otherSide) += lift;
        }
        EXPECT_GT(model.nodes.position[pulled].z(), 1e-4) << "the pulled piece follows";
        EXPECT_GT(sameSide, 1e-4);
        EXPECT_LT(otherSide, 1e-9 + 1e-3 * sameSide) << "the other piece does not feel it";
    }
}

TEST(ProgressiveCutter, AStrokeAcrossAnEarlierWoundCutsItsWallsDownToTheFloorAndGoesOnBeyondIt) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(12, 0.01));
    const double mass = physics::totalMass(cut.model());
    ProgressiveCutter cutter(cut);
    stroke(cut, cutter, Vec3(-0.035, 0.0043, 0), Vec3(0.035, 0.0043, 0), 140);  // the earlier wound
    ASSERT_EQ(countGroups(cut.mesh(), true), 1) << "the grid's rim only: walls close the wound";
    const long walls = cutter.stats().wallsClosed, cuts = cutter.stats().cuts;
    const double length = cutter.stats().length_m;
    std::vector<bool> oldFloor(cut.mesh().positions.size());
    for (std::uint32_t v = 0; v < oldFloor.size(); ++v) oldFloor[v] = cut.isFloor(v);
    const std::size_t oldFaces = cut.mesh().faces.size();
    stroke(cut, cutter, Vec3(0.0031, -0.03, 0), Vec3(0.0031, 0.03, 0), 120);  // across it
    const InvariantReport r = checkInvariants(cut, mass);
    ASSERT_TRUE(r.ok()) << r.problems.front();
    EXPECT_EQ(countGroups(cut.mesh(), true), 1) << "both wounds closed by their walls";
    EXPECT_EQ(countGroups(cut.mesh(), false), 1) << "and the grid is still one piece (joined under the floor)";
    EXPECT_GT(cutter.stats().wallsClosed, walls + 4);
    // One cut, through the first wound: down its near wall to the floor and up the far wall. Both lips
    // there opened, so the new cut's walls (on either side of the first wound) reach the old floor.
    EXPECT_EQ(cutter.stats().cuts, cuts + 1);
    EXPECT_EQ(cutter.stats().woundsCrossed, 1);
    EXPECT_NEAR(cutter.stats().length_m - length, 0.06, 0.01) << "along the surface, across the gap";
    int newWallsAtOldFloor = 0;
    double nearSide = 0, farSide = 0;
    for (std::size_t f = oldFaces; f < cut.mesh().faces.size(); ++f) {
        if (!cut.isWall(static_cast<std::uint32_t>(f))) continue;
        const mesh::Face& face = cut.mesh().faces[f];
        if (std::none_of(face.begin(), face.end(), [&](std::uint32_t v) { return v < oldFloor.size() && oldFloor[v]; }))
            continue;
        ++newWallsAtOldFloor;
        // Floors among the hole's corners (CutModel::closeOpening): one under the lip would make 2-3 degrees.
        EXPECT_GT(geometry::minAngle(cut.mesh().positions[face[0]], cut.mesh().positions[face[1]],
                                     cut.mesh().positions[face[2]]),
                  10 * 3.14159265358979323846 / 180);
        const double y =
            (cut.mesh().positions[face[0]] + cut.mesh().positions[face[1]] + cut.mesh().positions[face[2]]).y() / 3;
        (y < 0.0043 ? nearSide : farSide) += 1;
    }
    EXPECT_GE(nearSide, 2) << "the near wall is cut down to the floor";
    EXPECT_GE(farSide, 2) << "and the far wall";
    EXPECT_EQ(newWallsAtOldFloor, nearSide + farSide);
    double yMax = -1;
    for (std::uint32_t v = 0; v < cut.mesh().positions.size(); ++v) {
        const Vec3& p = cut.mesh().positions[v];
        if (std::abs(p.x() - 0.0031) < 0.006 && cut.floorUnder(v)) yMax = std::max(yMax, p.y());
    }
    EXPECT_GT(yMax, 0.02) << "the lips of the crossing cut reach well past the first wound";
}

TEST(ProgressiveCutter, WithoutWallsAStrokeAcrossAnEarlierWoundJoinsItIntoOneOpening) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(12, 0.01));
    const double mass = physics::totalMass(cut.model());
    ProgressiveCutter cutter(cut, CutterParams{.walls = false});
    stroke(cut, cutter, Vec3(-0.035, 0.0043, 0), Vec3(0.035, 0.0043, 0), 140);  // the earlier wound
    ASSERT_EQ(countGroups(cut.mesh(), true), 2) << "the grid's rim and the wound";
    stroke(cut, cutter, Vec3(0.0031, -0.03, 0), Vec3(0.0031, 0.03, 0), 120);  // across it
    const InvariantReport r = checkInvariants(cut, mass);
    ASSERT_TRUE(r.ok()) << r.problems.front();
    EXPECT_GE(cutter.stats().joins, 1);
    EXPECT_EQ(countGroups(cut.mesh(), true), 2) << "the two cuts are one opening, apart from the grid's rim";
    EXPECT_EQ(countGroups(cut.mesh(), false), 1) << "and the grid is still one piece";
}

// A stroke that turns back across its own wound: right, down, left under its first leg and up across
// it. The way on then crosses only the cut's own older lip, which it may not join (that would cut a loop
// of tissue free), so the cut ends there and the blade starts a new one beyond. Kept waiting, the cut
// never followed the blade again.
TEST(ProgressiveCutter, AStrokeThatTurnsBackAcrossItsOwnWoundEndsThereAndCutsOnBeyondIt) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(20, 0.005));
    const double mass = physics::totalMass(cut.model());
    ProgressiveCutter cutter(cut);
    const std::vector<Vec3> corners{Vec3(-0.032, 0.0043, 0), Vec3(0.028, 0.0043, 0), Vec3(0.028, -0.0157, 0),
                                    Vec3(-0.012, -0.0157, 0), Vec3(-0.012, 0.0243, 0)};
    double highest = -1;  // the farthest up the last leg a cut point lies, beyond the first leg
    for (std::size_t leg = 0; leg + 1 < corners.size(); ++leg)
        for (int i = 0; i <= 100; ++i) {
            const Vec3 at = corners[leg] + (corners[leg + 1] - corners[leg]) * (i / 100.0);
            const auto [face, bary] = touch(cut, at);
            cutter.cutAt(face, bary);
            if (leg == 3 && cutter.cutting())
                highest = std::max(highest, cut.mesh().positions[cutter.points().back()].y());
        }
    cutter.endCut();
    EXPECT_EQ(cutter.stats().cuts, 2) << "the first cut ends at its own wound, and a second starts beyond";
    EXPECT_GT(highest, 0.015) << "the second cut follows the blade up past the first leg";
    const InvariantReport r = checkInvariants(cut, mass);
    EXPECT_TRUE(r.ok()) << r.problems.front();
}

TEST(ProgressiveCutter, RandomStrokesOnTheHeartKeepEveryInvariant) {
    std::mt19937 rng(3);
    CutModel cut = cuttable(mesh::procedural::makeHeart({}));
    const double mass = physics::totalMass(cut.model());
    ProgressiveCutter cutter(cut);
    std::uniform_real_distribution<double> unit(-1, 1), length(0.005, 0.03);
    for (int i = 0; i < 150; ++i) {
        // Start on the surface at a random place, stroke in a random tangent direction.
        const Vec3 start = touchPoint(cut, randomVec3(unit, rng).normalized() * 0.1);
        const Vec3 dir = randomVec3(unit, rng).normalized();
        const Vec3 end = touchPoint(cut, start + length(rng) * dir);
        stroke(cut, cutter, start, end, 1 + static_cast<int>(rng() % 30));
        const InvariantReport r = checkInvariants(cut, mass, /*closed=*/true);
        ASSERT_TRUE(r.ok()) << "after stroke " << i << ": " << r.problems.front();
    }
    EXPECT_GT(cutter.stats().cutPoints, 500);
    EXPECT_GT(cutter.stats().wallsClosed, 300);
    EXPECT_TRUE(cutter.stats().opened);
    physics::Stepper stepper(physics::Scheme::RungeKutta4);
    stepper.setAutoSubstep(false);
    stepper.prepare(cut.model());
    for (int i = 0; i < 100; ++i) ASSERT_TRUE(stepper.step(cut.model(), stepper.stableStep_s()).finite);
}

}  // namespace
}  // namespace hapticut::cutting
