// The active region (local simulation): the same motion as simulating every node, with only the
// nodes near the tool awake, and everything asleep again once the tissue has come to rest.
#include <gtest/gtest.h>

#include <algorithm>

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"
#include "test_support.h"

namespace hapticut::physics {
namespace {

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

// The snap rule (R4) puts a node that is almost at rest back at rest. A node that its springs pull harder
// than its anchor holds within the snap distance is left where the step took it: put back, it could never
// leave rest where the springs' pull gives way as it moves (its place of balance is within the snap
// distance), and it stayed awake, pulled, and put back every step, with the solve working out its motion
// only to have it undone.
TEST(ActiveRegion, NoAwakeNodeIsHeldAtRestByTheSnapRule) {
    mesh::procedural::HeartOptions options;
    options.triangles = 9714;
    const mesh::SurfaceMesh mesh = mesh::procedural::makeHeart(options);
    MassSpringModel model = buildModel(mesh, Material{});
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

}  // namespace
}  // namespace hapticut::physics
