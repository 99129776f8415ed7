// Topology edits for cutting: face and edge splits against hand-counted results, and thousands of
// random splits with every invariant checked, after which the model still simulates.
#include <gtest/gtest.h>

#include <random>

#include "cutting/cuttable.h"
#include "hapticut/cutting/cut_model.h"
#include "hapticut/cutting/invariants.h"
#include "hapticut/geometry/random_vec.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/physics/integrators.h"

namespace hapticut::cutting {
namespace {

using test::cuttable;

TEST(CutModel, SplittingAFaceAddsAVertexTwoFacesAndThreeSprings) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(4, 0.01));
    const double mass = physics::totalMass(cut.model());
    const std::size_t v0 = cut.mesh().positions.size(), f0 = cut.mesh().faces.size(), s0 = cut.model().springs.size();
    const mesh::Face face = cut.mesh().faces[5];
    const mesh::FaceUvs uv = cut.mesh().uvs[5];
    const Vec3 bary(0.2, 0.3, 0.5);
    const std::uint32_t k = cut.splitFace(5, bary);
    EXPECT_EQ(k, v0);
    EXPECT_EQ(cut.mesh().positions.size(), v0 + 1);
    EXPECT_EQ(cut.mesh().faces.size(), f0 + 2);
    EXPECT_EQ(cut.model().springs.size(), s0 + 3);
    const Vec3 expected =
        0.2 * cut.mesh().positions[face[0]] + 0.3 * cut.mesh().positions[face[1]] + 0.5 * cut.mesh().positions[face[2]];
    EXPECT_LT((cut.mesh().positions[k] - expected).norm(), 1e-15) << "rest position on the undeformed face";
    EXPECT_NEAR(cut.mesh().positions[k].z(), 0, 1e-15);
    for (std::uint32_t v : face) {
        const auto spring = cut.springOf(v, k);
        ASSERT_TRUE(spring.has_value());
        EXPECT_NEAR(cut.model().springs.restLength[*spring], (cut.mesh().positions[v] - expected).norm(), 1e-15);
    }
    // The new corner's UV is the barycentric mix of the face's UVs.
    const Vec2 uvk = 0.2 * uv[0] + 0.3 * uv[1] + 0.5 * uv[2];
    EXPECT_LT((cut.mesh().uvs[5][2] - uvk).norm(), 1e-15);
    EXPECT_NEAR(physics::totalMass(cut.model()), mass, 1e-15);
    const InvariantReport r = checkInvariants(cut, mass);
    EXPECT_TRUE(r.ok()) << r.problems.front();
    EXPECT_EQ(mesh::validateMesh(cut.mesh()).boundaryEdges, 16u) << "a face split opens nothing";
}

TEST(CutModel, SplittingAnEdgeSplitsBothFacesAndTheSpring) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(4, 0.01));
    const double mass = physics::totalMass(cut.model());
    const std::size_t v0 = cut.mesh().positions.size(), f0 = cut.mesh().faces.size(), s0 = cut.model().springs.size();
    // An interior edge: the diagonal of the first quad, (0, 6).
    ASSERT_EQ(cut.facesOfEdge(0, 6).size(), 2u);
    const std::uint32_t p = cut.splitEdge(0, 6, 0.25);
    EXPECT_EQ(cut.mesh().faces.size(), f0 + 2);
    EXPECT_EQ(cut.model().springs.size(), s0 + 3);
    EXPECT_FALSE(cut.springOf(0, 6).has_value()) << "the old edge is gone";
    EXPECT_LT((cut.mesh().positions[p] - (0.75 * cut.mesh().positions[0] + 0.25 * cut.mesh().positions[6])).norm(),
              1e-15);
    EXPECT_NEAR(physics::totalMass(cut.model()), mass, 1e-15);
    // A boundary edge has one face.
    ASSERT_EQ(cut.facesOfEdge(0, 1).size(), 1u);
    cut.splitEdge(0, 1, 0.5);
    EXPECT_EQ(cut.mesh().positions.size(), v0 + 2);
    EXPECT_EQ(cut.mesh().faces.size(), f0 + 3);
    const InvariantReport r = checkInvariants(cut, mass);
    EXPECT_TRUE(r.ok()) << r.problems.front();
    EXPECT_EQ(mesh::validateMesh(cut.mesh()).boundaryEdges, 17u) << "the split boundary edge is two boundary edges";
}

TEST(CutModel, SnapsToACornerWithinTheRadius) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(4, 0.01));
    const mesh::Face face = cut.mesh().faces[0];
    EXPECT_EQ(cut.snapVertex(0, Vec3(0.97, 0.02, 0.01), 0.001), face[0]);
    EXPECT_FALSE(cut.snapVertex(0, Vec3(0.4, 0.3, 0.3), 0.001).has_value());
}

TEST(CutModel, AskedToItKeepsThePositionsArrayACutOutgrowsAndTheViewsOfItStayReadable) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(4, 0.01));
    cut.keepRetiredPositions(true);
    const std::vector<Vec3>& positions = cut.model().nodes.position;
    const Vec3* viewed = positions.data();  // what a view taken now points at
    const std::size_t room = positions.capacity(), before = positions.size();
    std::vector<Vec3> seen(positions.begin(), positions.end());
    std::size_t splits = 0;
    while (positions.data() == viewed) {
        EXPECT_TRUE(cut.takeRetiredPositions().empty()) << "nothing retired while the array has room";
        cut.splitFace(static_cast<std::uint32_t>(splits++ % cut.mesh().faces.size()), Vec3(0.3, 0.3, 0.4));
    }
    EXPECT_EQ(before + splits, room + 1) << "it moved when, and only when, it was full";
    std::vector<std::vector<Vec3>> retired = cut.takeRetiredPositions();
    ASSERT_EQ(retired.size(), 1u);
    EXPECT_EQ(retired[0].data(), viewed) << "the very array the views point at, not a copy";
    ASSERT_GE(retired[0].size(), seen.size());
    for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(retired[0][i], seen[i]);
    EXPECT_GE(positions.capacity(), positions.size() + positions.size() / 3) << "grown with room to spare";
    EXPECT_TRUE(cut.takeRetiredPositions().empty()) << "handed over once";
    const InvariantReport r = checkInvariants(cut, physics::totalMass(cut.model()));
    EXPECT_TRUE(r.ok()) << r.problems.front();
}

TEST(CutModel, InvariantsCatchABrokenModel) {
    CutModel cut = cuttable(mesh::procedural::makeGrid(2, 0.01));
    EXPECT_FALSE(checkInvariants(cut, 1.0).ok()) << "wrong mass";
    cut.model().nodes.position[0].x() = std::nan("");
    const InvariantReport r = checkInvariants(cut, physics::totalMass(cut.model()));
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.problems.front().find("not finite"), std::string::npos) << r.problems.front();

    // Two triangles touching only at vertex 0: edge-manifold, but pinched at a vertex.
    mesh::SurfaceMesh bowtie;
    bowtie.positions = {Vec3(0, 0, 0), Vec3(0.01, 0, 0), Vec3(0.01, 0.01, 0), Vec3(-0.01, 0, 0), Vec3(-0.01, -0.01, 0)};
    bowtie.faces = {{0, 1, 2}, {0, 3, 4}};
    bowtie.uvs.assign(2, mesh::FaceUvs{});
    bowtie.edges = mesh::edgesOfFaces(bowtie.faces);
    CutModel pinched = cuttable(bowtie);
    const InvariantReport p = checkInvariants(pinched, physics::totalMass(pinched.model()));
    ASSERT_FALSE(p.ok());
    EXPECT_NE(p.problems.front().find("vertex 0 joins 2 fans"), std::string::npos) << p.problems.front();
    // separateFans is the cure: vertex 0 gets a copy for the second fan, and every invariant holds.
    EXPECT_EQ(pinched.separateFans(0), 1);
    const InvariantReport fixed = checkInvariants(pinched, physics::totalMass(cuttable(bowtie).model()));
    EXPECT_TRUE(fixed.ok()) << fixed.problems.front();
    EXPECT_EQ(pinched.mesh().positions.size(), 6u);
}

/// One random split: a face at a random interior point, or one of its edges at a random point. The new
/// vertex must sit exactly where it was asked for, at rest and deformed.
void randomSplit(CutModel& cut, std::mt19937& rng) {
    std::uniform_int_distribution<std::uint32_t> pickFace(0, static_cast<std::uint32_t>(cut.mesh().faces.size() - 1));
    std::uniform_real_distribution<double> u(0.15, 0.85);
    const std::uint32_t f = pickFace(rng);
    const mesh::Face face = cut.mesh().faces[f];
    const auto& rest = cut.mesh().positions;
    if (rng() % 2) {
        Vec3 bary = randomVec3(u, rng);
        bary /= bary.sum();
        const Vec3 expected = bary.x() * rest[face[0]] + bary.y() * rest[face[1]] + bary.z() * rest[face[2]];
        const std::uint32_t v = cut.splitFace(f, bary);
        ASSERT_LT((cut.mesh().positions[v] - expected).norm(), 1e-12);
    } else {
        const int k = static_cast<int>(rng() % 3);
        const double t = u(rng);
        const Vec3 expected = (1 - t) * rest[face[k]] + t * rest[face[(k + 1) % 3]];
        const std::uint32_t v = cut.splitEdge(face[k], face[(k + 1) % 3], t);
        ASSERT_LT((cut.mesh().positions[v] - expected).norm(), 1e-12);
    }
}

TEST(CutModel, ThousandsOfRandomSplitsKeepEveryInvariant) {
    std::mt19937 rng(7);
    CutModel cut = cuttable(mesh::procedural::makeSphere(Vec3::Zero(), 0.05, 12, 8));
    const double mass = physics::totalMass(cut.model());
    for (int i = 0; i < 2000; ++i) {
        randomSplit(cut, rng);
        const InvariantReport r = checkInvariants(cut, mass);
        ASSERT_TRUE(r.ok()) << "after split " << i << ": " << r.problems.front();
    }
    const mesh::MeshReport after = mesh::validateMesh(cut.mesh());
    EXPECT_TRUE(after.closed);
    EXPECT_EQ(after.eulerCharacteristic, 2);
}

TEST(CutModel, TheHeartStillSimulatesAfterTenThousandSplits) {
    std::mt19937 rng(11);
    CutModel cut = cuttable(mesh::procedural::makeHeart({}));
    const double mass = physics::totalMass(cut.model());
    for (int i = 0; i < 10'000; ++i) {
        randomSplit(cut, rng);
        if (i % 500 == 499) {
            const InvariantReport r = checkInvariants(cut, mass);
            ASSERT_TRUE(r.ok()) << "after split " << i << ": " << r.problems.front();
        }
    }
    // Random splits make tiny, stiff triangles (the cutter will snap instead), so step at the model's
    // own stable step rather than substepping 1 ms: the point is that the model is sound.
    physics::MassSpringModel& model = cut.model();
    physics::Stepper stepper(physics::Scheme::RungeKutta4);
    stepper.setAutoSubstep(false);
    stepper.prepare(model);
    ASSERT_GT(stepper.stableStep_s(), 0.0);
    model.nodes.externalForce[100] = Vec3(0, 0, -0.5);
    for (int i = 0; i < 200; ++i) ASSERT_TRUE(stepper.step(model, stepper.stableStep_s()).finite) << "step " << i;
    EXPECT_GT(physics::maxDisplacement(model), 0.0);
    EXPECT_NEAR(physics::totalMass(model), mass, 1e-12);
}

}  // namespace
}  // namespace hapticut::cutting

namespace hapticut::cutting {
namespace {

/// The thesis's figure 3.6 on a flat 8 x 8 grid: a straight cut left to right along the middle row
/// of vertices c0 ... c4, each new point opening the one before.
TEST(OpenCut, AStraightCutOpensProgressivelyAndTheLipsSeparate) {
    const int n = 8;
    CutModel cut = cuttable(mesh::procedural::makeGrid(n, 0.01));
    const double mass = physics::totalMass(cut.model());
    auto vertex = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    std::vector<std::uint32_t> points;
    for (int i = 2; i <= 6; ++i) points.push_back(vertex(i, 4));
    const std::size_t boundary0 = mesh::validateMesh(cut.mesh()).boundaryEdges;
    std::vector<std::uint32_t> copies;
    for (std::size_t i = 2; i < points.size(); ++i) {
        const auto copy = cut.openCut(points[i - 2], points[i - 1], points[i]);
        ASSERT_TRUE(copy.has_value()) << "opening point " << i - 1;
        copies.push_back(*copy);
        const InvariantReport r = checkInvariants(cut, mass);
        ASSERT_TRUE(r.ok()) << r.problems.front();
    }
    // Three openings: the cut's four edges appear twice each as boundary (both lips).
    const mesh::MeshReport after = mesh::validateMesh(cut.mesh());
    EXPECT_EQ(after.vertices, static_cast<std::size_t>((n + 1) * (n + 1) + 3));
    EXPECT_EQ(after.boundaryEdges, boundary0 + 8);
    EXPECT_TRUE(after.manifold);
    EXPECT_TRUE(after.oriented);
    // The left lip lies above the cut (+y): the duplicate of c1 is used by faces above the row.
    for (std::uint32_t f : cut.facesAround(copies[0])) {
        const mesh::Face& face = cut.mesh().faces[f];
        for (std::uint32_t v : face)
            EXPECT_GE(cut.mesh().positions[v].y(), cut.mesh().positions[points[1]].y() - 1e-12);
    }
    // Shortened springs pull the lips apart, and they stay apart. With the default material the
    // anchors are far stiffer than the edge springs, so the gap is tens of micrometres.
    physics::MassSpringModel& model = cut.model();
    physics::Stepper stepper(physics::Scheme::RungeKutta4);
    auto gap = [&] { return (model.nodes.position[points[2]] - model.nodes.position[copies[1]]).norm(); };
    EXPECT_EQ(gap(), 0.0);
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(stepper.step(model, 1e-3).finite);
    EXPECT_GT(gap(), 1e-5) << "the lips separate";
    for (int i = 0; i < 500; ++i) ASSERT_TRUE(stepper.step(model, 1e-3).finite);
    EXPECT_GT(gap(), 1e-5) << "and stay apart at rest";
    // Above the cut the duplicate moves up (+y), below it the original moves down.
    EXPECT_GT(model.nodes.position[copies[1]].y(), model.nodes.position[points[2]].y());
}

TEST(OpenCut, CutsAlongAPathOnTheHeartKeepEveryInvariant) {
    CutModel cut = cuttable(mesh::procedural::makeHeart({}));
    const double mass = physics::totalMass(cut.model());
    // A path of edges across the front: from the vertex nearest each waypoint, step to the
    // neighbour that gets closest to the next waypoint.
    std::vector<std::uint32_t> path;
    auto nearest = [&](const Vec3& p) {
        std::uint32_t best = 0;
        for (std::uint32_t v = 0; v < cut.mesh().positions.size(); ++v)
            if ((cut.mesh().positions[v] - p).norm() < (cut.mesh().positions[best] - p).norm()) best = v;
        return best;
    };
    path.push_back(nearest(Vec3(-0.025, -0.01, 0.04)));
    const std::uint32_t goal = nearest(Vec3(0.025, -0.01, 0.04));
    while (path.back() != goal && path.size() < 40) {
        std::uint32_t best = path.back();
        for (std::uint32_t f : cut.facesAround(path.back()))
            for (std::uint32_t v : cut.mesh().faces[f])
                if ((cut.mesh().positions[v] - cut.mesh().positions[goal]).norm() <
                    (cut.mesh().positions[best] - cut.mesh().positions[goal]).norm())
                    best = v;
        if (best == path.back()) break;
        path.push_back(best);
    }
    ASSERT_GE(path.size(), 5u);
    for (std::size_t i = 2; i < path.size(); ++i) {
        ASSERT_TRUE(cut.openCut(path[i - 2], path[i - 1], path[i]).has_value()) << "point " << i - 1;
        const InvariantReport r = checkInvariants(cut, mass);
        ASSERT_TRUE(r.ok()) << "after opening point " << i - 1 << ": " << r.problems.front();
    }
    EXPECT_EQ(mesh::validateMesh(cut.mesh()).boundaryEdges, 2 * (path.size() - 1));
    physics::Stepper stepper(physics::Scheme::RungeKutta4);
    for (int i = 0; i < 300; ++i) ASSERT_TRUE(stepper.step(cut.model(), 1e-3).finite);
    EXPECT_GT(physics::maxDisplacement(cut.model()), 1e-5) << "the wound pulls open";
}

}  // namespace
}  // namespace hapticut::cutting
