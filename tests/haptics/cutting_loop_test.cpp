// The scalpel in the haptic loop: pressed past its threshold it cuts along the device's path and the
// wound opens; the probe on the same path cuts nothing; the renderer's snapshot follows the new faces.
#include <gtest/gtest.h>

#include <algorithm>

#include "hapticut/cutting/invariants.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"

namespace hapticut::haptics {
namespace {

/// Down onto the front of the heart 12 mm deep at x = -2 cm, across to x = +2 cm in 1 s, and up.
Trajectory strokeAcrossTheFront(double depth_m) {
    const double z = 0.0302 - depth_m;  // the front surface is near z = 3.0 cm at y = -1 cm
    Trajectory t;
    auto at = [&](double time, double x, double zz) {
        TrajectoryPoint p;
        p.t_s = time;
        p.sample.position_m = Vec3(x, -0.01, zz);
        t.points.push_back(p);
    };
    at(0.0, -0.02, 0.06);
    at(0.6, -0.02, 0.033);
    at(0.9, -0.02, z);
    at(1.9, 0.02, z);
    at(2.2, 0.02, 0.06);
    return t;
}

struct StrokeResult {
    cutting::CutStats cut;
    long cutEvents = 0;
    mesh::MeshReport after;
    std::vector<std::string> problems;
    std::size_t snapshotFaces = 0, facesAfter = 0, wallFaces = 0;
    long snapshotsChecked = 0, snapshotMismatches = 0;
    std::vector<Vec3> cutPoints;
    double maxForce_N = 0;
};

StrokeResult stroke(double threshold_N, double depth_m) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
    const double mass = physics::totalMass(organ.model());
    ReplayDevice device(strokeAcrossTheFront(depth_m));
    LoopConfig config;
    config.cutThreshold_N = threshold_N;
    HapticLoop loop(organ, device, config);
    StrokeResult r;
    long step = 0;
    runSimulated(loop, 2300, [&](const StepOutput& s) {
        if (s.cut)
            for (std::uint32_t v : loop.cutter().points()) r.cutPoints.push_back(organ.mesh().positions[v]);
        // Now and then, as a renderer does, so that the other slots fall several cuts behind and must
        // catch up on every face changed since: the snapshot published with a cut shows exactly the organ.
        if (s.cut && ++step % 3 == 0) {
            const Snapshot& shot = loop.snapshots().readLatest();
            r.snapshotsChecked += 1;
            r.snapshotMismatches += shot.faces != organ.mesh().faces || shot.uvs.size() != organ.mesh().uvs.size();
            // Its nodes too: the ones the cuts added since a slot was written, and the ones that moved.
            r.snapshotMismatches += shot.positions != organ.model().nodes.position;
            for (std::size_t f = 0; f < std::min(shot.uvs.size(), organ.mesh().uvs.size()); ++f)
                for (int k = 0; k < 3; ++k) r.snapshotMismatches += shot.uvs[f][k] != organ.mesh().uvs[f][k];
        }
    });
    r.cut = loop.cutter().stats();
    r.cutEvents = loop.stats().cutEvents;
    r.maxForce_N = loop.stats().maxForce_N;
    r.after = mesh::validateMesh(organ.mesh());
    r.problems = cutting::checkInvariants(organ, mass, organ.closedBeforeCuts()).problems;
    r.wallFaces =
        static_cast<std::size_t>(std::count(organ.wallFaces().begin(), organ.wallFaces().end(), std::uint8_t{1}));
    r.snapshotFaces = loop.snapshots().readLatest().faces.size();
    r.facesAfter = organ.mesh().faces.size();
    EXPECT_FALSE(loop.stats().watchdogTripped);
    EXPECT_EQ(loop.stats().nonFiniteEvents, 0);
    return r;
}

TEST(CuttingLoop, AScalpelPressedPastItsThresholdCutsAlongTheStrokeAndTheWoundOpens) {
    const StrokeResult r = stroke(mesh::procedural::kScalpelThreshold_N, 0.012);
    ASSERT_TRUE(r.problems.empty()) << r.problems.front();
    EXPECT_TRUE(r.cut.opened);
    EXPECT_GE(r.cut.cutPoints, 8);
    EXPECT_GT(r.cutEvents, 5) << "the cut grows step by step with the blade, not in one jump";
    // Along the stroke: on the front (z > 0), near y = -1 cm, spanning most of the 4 cm in x.
    double xMin = 1, xMax = -1;
    for (const Vec3& p : r.cutPoints) {
        EXPECT_GT(p.z(), 0.0);
        EXPECT_NEAR(p.y(), -0.01, 0.008);
        xMin = std::min(xMin, p.x()), xMax = std::max(xMax, p.x());
    }
    EXPECT_GT(xMax - xMin, 0.02);
    EXPECT_LT(xMin, 0.0);
    EXPECT_GT(xMax, 0.015);
    // Every opened point's gap is closed with walls down to a floor: the heart stays closed, one
    // manifold piece, four wall faces to each opening.
    EXPECT_GE(r.cut.wallsClosed, r.cut.cutPoints - 3);
    EXPECT_EQ(r.wallFaces, 4 * static_cast<std::size_t>(r.cut.wallsClosed));
    EXPECT_EQ(r.after.boundaryEdges, 0u);
    EXPECT_TRUE(r.after.closed);
    EXPECT_TRUE(r.after.manifold);
    EXPECT_TRUE(r.after.oriented);
    EXPECT_GT(r.after.minAngleDeg, 5.0);
    EXPECT_EQ(r.snapshotFaces, r.facesAfter) << "the renderer sees the cut";
    EXPECT_GE(r.snapshotsChecked, 3);
    EXPECT_EQ(r.snapshotMismatches, 0) << "a snapshot's nodes, faces or UVs differ from the organ's";
}

TEST(CuttingLoop, TheProbeOnTheSamePathCutsNothing) {
    const StrokeResult r = stroke(mesh::procedural::kProbeThreshold_N, 0.012);
    EXPECT_EQ(r.cut.cutPoints, 0);
    EXPECT_EQ(r.cutEvents, 0);
    EXPECT_TRUE(r.after.closed);
    EXPECT_EQ(r.after.faces, mesh::procedural::makeHeart({}).faces.size());
}

TEST(CuttingLoop, AScalpelPressedLightlyDoesNotCut) {
    const StrokeResult r = stroke(mesh::procedural::kScalpelThreshold_N, 0.0015);
    EXPECT_GT(r.maxForce_N, 0.2) << "it did press";
    EXPECT_LT(r.maxForce_N, mesh::procedural::kScalpelThreshold_N);
    EXPECT_EQ(r.cut.cutPoints, 0);
    EXPECT_TRUE(r.after.closed);
}

}  // namespace
}  // namespace hapticut::haptics
