// The active region (local simulation): the same motion as simulating every node, with only the
// nodes near the tool awake, and everything asleep again once the tissue has come to rest.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/active_region.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"
#include "hapticut/physics/node_springs.h"
#include "hapticut/physics/spring_forces.h"
#include "test_support.h"

namespace hapticut::physics {
namespace {

/// The procedural heart's model at `triangles` triangles, with the default material.
MassSpringModel heartModel(int triangles) {
    mesh::procedural::HeartOptions options;
    options.triangles = triangles;
    return buildModel(mesh::procedural::makeHeart(options), Material{});
}

TEST(ActiveRegion, MatchesTheFullSimulationWhileOnlyTheRegionNearTheToolIsAwake) {
    mesh::procedural::HeartOptions options;
    options.triangles = 9714;
    const mesh::SurfaceMesh mesh = mesh::procedural::makeHeart(options);
    MassSpringModel full = buildModel(mesh, Material{}), local = full;
    Stepper fullStepper(Scheme::RungeKutta4), localStepper(Scheme::RungeKutta4);
    fullStepper.setToolStiffness(400);
    localStepper.setToolStiffness(400);
    localStepper.setActiveRegion(true);
    std::size_t largestRegion = 0, unsortedSteps = 0;
    double worst = 0, largestDisplacement = 0;
    for (int step = 0; step < 800; ++step) {
        test::pressFrontWithTool(full, mesh, step);
        test::pressFrontWithTool(local, mesh, step);
        ASSERT_TRUE(fullStepper.step(full, 1e-3).finite);
        ASSERT_TRUE(localStepper.step(local, 1e-3).finite);
        largestRegion = std::max(largestRegion, localStepper.awakeCount());
        // The awake nodes, the solve's unknowns, in the organ's vertex order whatever order they woke in.
        const std::span<const std::uint32_t> awake = localStepper.movedNodes();
        unsortedSteps += !std::is_sorted(awake.begin(), awake.end());
        largestDisplacement = std::max(largestDisplacement, maxDisplacement(full));
        for (std::size_t i = 0; i < full.nodes.size(); ++i)
            worst = std::max(worst, (full.nodes.position[i] - local.nodes.position[i]).norm());
    }
    EXPECT_GT(largestDisplacement, 1e-3) << "the press must really deform the tissue";
    // Nodes wake one step after their neighbours pull on them; the motion differs by a small fraction.
    EXPECT_LT(worst, 0.01 * largestDisplacement) << "worst difference " << worst << " m";
    EXPECT_LT(largestRegion, full.nodes.size() / 3) << "the region stays local";
    EXPECT_GT(largestRegion, 3u);
    EXPECT_EQ(unsortedSteps, 0u);
    EXPECT_EQ(localStepper.awakeCount(), 0u) << "asleep again 0.5 s after the tool left";
    EXPECT_EQ(maxDisplacement(local), 0.0);
}

TEST(ActiveRegion, WakesOnRequestForAnExternalForce) {
    MassSpringModel model = buildModel(mesh::procedural::makeHeart({}), Material{});
    Stepper stepper(Scheme::RungeKutta4);
    stepper.setActiveRegion(true);
    (void)stepper.step(model, 1e-3);
    EXPECT_EQ(stepper.awakeCount(), 0u);
    model.nodes.externalForce[42] = Vec3(0, 0, -1);
    (void)stepper.step(model, 1e-3);
    EXPECT_EQ(maxDisplacement(model), 0.0) << "a sleeping node ignores a force until woken";
    stepper.wake(42);
    for (int i = 0; i < 100; ++i) (void)stepper.step(model, 1e-3);
    EXPECT_GT((model.nodes.position[42] - model.nodes.restPosition[42]).norm(), 1e-3);
}

// The snap rule (R4) puts a node that is almost at rest back at rest. A node that its springs pull off rest
// (it would settle beyond the snap distance) is left where the step took it: put back, it could never
// leave rest where the springs' pull gives way as it moves (its place of balance is within the snap
// distance), and it stayed awake, pulled, and put back every step, with the solve working out its motion
// only to have it undone.
TEST(ActiveRegion, NoAwakeNodeIsHeldAtRestByTheSnapRule) {
    MassSpringModel model = heartModel(9714);
    Stepper stepper(Scheme::BackwardEuler);
    stepper.setActiveRegion(true);
    (void)stepper.step(model, 1e-3);  // prepared, and every node asleep at rest
    model.nodes.externalForce[42] = Vec3(0, 0, 0.2);
    stepper.wake(42);
    int iterations = -1;
    for (int i = 0; i < 2000; ++i) iterations = stepper.step(model, 1e-3).solve.iterations;
    std::size_t heldAtRest = 0;
    for (std::uint32_t i : stepper.movedNodes()) heldAtRest += model.nodes.position[i] == model.nodes.restPosition[i];
    // Without the exception 2 nodes were held at rest here, and the solve took 2 iterations a step for them.
    EXPECT_GT(stepper.awakeCount(), 10u) << "the load moves a patch";
    EXPECT_EQ(heldAtRest, 0u) << "of " << stepper.awakeCount() << " awake nodes";
    EXPECT_EQ(iterations, 0) << "settled: nothing left to solve";
}

/// Where node i settles under `force` with every other node held where it is: the static solution,
/// found by the implicit stepper with long steps, the snap rule off.
Vec3 settledAlone(MassSpringModel model, std::uint32_t i, const Vec3& force) {
    for (std::uint32_t k = 0; k < model.nodes.size(); ++k)
        if (k != i) model.nodes.inverseMass[k] = 0;
    model.nodes.externalForce[i] = force;
    model.snapDistance_m = model.snapSpeed_m_per_s = 0;
    Stepper stepper(Scheme::BackwardEuler);
    SolverSettings exact = stepper.solverSettings();
    exact.tolerance = 1e-12, exact.forceTolerance_N = 0;
    stepper.setSolverSettings(exact);
    for (int step = 0; step < 200; ++step) EXPECT_TRUE(stepper.step(model, 1.0).finite);
    return model.nodes.position[i] - model.nodes.restPosition[i];
}

// The snap rule lets a node rest where it would settle within the snap distance if it alone were let
// go: its springs to the neighbours hold it as well as its anchor. Judged by the anchor alone, the edge
// of a held press's region woke and fell asleep again every step (below).
TEST(ActiveRegion, ANodeRestsWhereItWouldSettleWithinTheSnapDistance) {
    MassSpringModel model = buildModel(test::tetrahedron(), Material{});
    // A node of small area, as in fine meshes: its springs hold it far more than its anchor does.
    for (double& k : model.springs.stiffness) k = 30 * model.nodes.anchorStiffness[0];
    NodeSprings springsAt;
    springsAt.build(model.springs, model.nodes.size());
    const Vec3 along = Vec3(0.3, -0.5, 0.8).normalized();
    const double probe_N = 1e-3, reach = model.snapDistance_m;
    const double settled = settledAlone(model, 0, probe_N * along).norm();
    ASSERT_GT(settled, 0);
    const double limit_N = probe_N * reach / settled;  // the force that moves it exactly the snap distance
    EXPECT_GT(0.9 * limit_N, 10 * model.nodes.anchorStiffness[0] * reach) << "the anchor alone would not hold it";
    EXPECT_FALSE(ActiveRegion::pulledOffRest(model, springsAt, 0, 0.9 * limit_N * along));
    EXPECT_TRUE(ActiveRegion::pulledOffRest(model, springsAt, 0, 1.1 * limit_N * along));

    // With no anchor and its springs in a plane, nothing holds it across that plane, however light the pull.
    model.nodes.anchorStiffness[0] = 0;
    const std::uint32_t dropped = springsAt.of(0)[0];
    model.springs.stiffness[dropped] = 0;
    std::vector<Vec3> ends;
    for (const std::uint32_t s : springsAt.of(0))
        if (s != dropped)
            ends.push_back(model.nodes.position[NodeSprings::otherEnd(model.springs, s, 0)] - model.nodes.position[0]);
    ASSERT_EQ(ends.size(), 2u);
    const Vec3 across = ends[0].cross(ends[1]).normalized();
    EXPECT_TRUE(ActiveRegion::pulledOffRest(model, springsAt, 0, 1e-12 * across));
    EXPECT_FALSE(ActiveRegion::pulledOffRest(model, springsAt, 0, Vec3::Zero()));
}

// A press held on the 50,000 heart: once the tissue has settled, the same nodes stay awake. With the
// rule judged by the anchors alone, the region's edge changed in 18 of these 400 steps (and in every
// step on the 100,000 heart), and each change laid the solve out afresh.
TEST(ActiveRegion, AHeldPressKeepsTheSameAwakeNodes) {
    MassSpringModel model = heartModel(50000);
    Stepper stepper(Scheme::BackwardEuler);
    stepper.setActiveRegion(true);
    (void)stepper.step(model, 1e-3);  // prepared, and every node asleep at rest
    std::uint32_t front = 0;
    for (std::uint32_t i = 0; i < model.nodes.size(); ++i)
        if (model.nodes.restPosition[i].z() > model.nodes.restPosition[front].z()) front = i;
    model.nodes.externalForce[front] = Vec3(0, 0, -1);
    stepper.wake(front);
    for (int step = 0; step < 1000; ++step) ASSERT_TRUE(stepper.step(model, 1e-3).finite);
    const std::vector<std::uint32_t> settled(stepper.movedNodes().begin(), stepper.movedNodes().end());
    int changed = 0;
    for (int step = 0; step < 400; ++step) {
        ASSERT_TRUE(stepper.step(model, 1e-3).finite);
        changed += !std::ranges::equal(stepper.movedNodes(), settled);
    }
    EXPECT_GT(settled.size(), 100u) << "the load moves a patch";
    EXPECT_EQ(changed, 0) << "steps of 400 whose awake nodes differed from the settled ones";
    EXPECT_GT((model.nodes.position[front] - model.nodes.restPosition[front]).norm(), 1e-3);
}

// After a step the sleep rule reads the forces on the nodes at rest, summed over each node's own springs
// where they are few: the same forces, to rounding, as the pass over the region's springs gives.
TEST(ActiveRegion, ANodesOwnSpringsGiveTheRegionsForceOnIt) {
    MassSpringModel model = heartModel(9714);
    Stepper stepper(Scheme::BackwardEuler);
    stepper.setActiveRegion(true);
    (void)stepper.step(model, 1e-3);
    model.nodes.externalForce[42] = Vec3(0.3, -0.2, 0.5);
    stepper.wake(42);
    for (int step = 0; step < 30; ++step) ASSERT_TRUE(stepper.step(model, 1e-3).finite);  // still moving
    const std::span<const std::uint32_t> nodes = stepper.movedNodes();
    std::vector<std::uint8_t> awake(model.nodes.size(), 0);
    for (const std::uint32_t i : nodes) awake[i] = 1;
    std::vector<std::uint32_t> touched(nodes.begin(), nodes.end()), springs;
    std::vector<std::uint8_t> listed = awake;
    for (std::uint32_t k = 0; k < model.springs.size(); ++k) {
        if (!awake[model.springs.a[k]] && !awake[model.springs.b[k]]) continue;
        springs.push_back(k);
        for (const std::uint32_t j : {model.springs.a[k], model.springs.b[k]})
            if (!listed[j]) listed[j] = 1, touched.push_back(j);
    }
    ASSERT_GT(touched.size(), nodes.size()) << "the region has resting neighbours";
    NodeSprings springsAt;
    springsAt.build(model.springs, model.nodes.size());
    std::vector<Vec3> region(model.nodes.size()), own(model.nodes.size());
    ForceRows rows;
    computeActiveAccelerations(model, model.nodes.position, model.nodes.velocity, region, nodes, touched, springs,
                               rows);
    computeListedAccelerations(model, model.nodes.position, model.nodes.velocity, own, touched, awake, springsAt);
    for (const std::uint32_t i : touched)
        EXPECT_LE((own[i] - region[i]).norm(), 1e-9 * (region[i].norm() + 1e-9)) << "node " << i;
}

}  // namespace
}  // namespace hapticut::physics
