// The multilevel preconditioner: a symmetric positive definite operator (what conjugate gradients
// needs), levels that shrink a surface by about its neighbour count, pinned nodes left out, the same
// solution as block-Jacobi in a fraction of the iterations where block-Jacobi needs many, and auto's
// switch between them.
#include <gtest/gtest.h>

#include <random>

#include "hapticut/geometry/random_vec.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/backward_euler.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"
#include "test_support.h"

namespace hapticut::physics {
namespace {

mesh::SurfaceMesh heartOf(int triangles) {
    mesh::procedural::HeartOptions options;
    options.triangles = triangles;
    return mesh::procedural::makeHeart(options);
}

/// The heart's backward-Euler system for a step of h, every node awake, with its nodes jostled off rest.
struct AssembledHeart {
    MassSpringModel model;
    std::vector<std::uint32_t> nodes, springs;
    BackwardEulerSystem system;

    AssembledHeart(int triangles, double h) : model(buildModel(heartOf(triangles), Material{})) {
        std::mt19937 rng(7);
        std::normal_distribution<double> noise(0, 2e-4);
        for (std::size_t i = 0; i < model.nodes.size(); ++i) model.nodes.position[i] += randomVec3(noise, rng);
        for (std::uint32_t i = 0; i < model.nodes.size(); ++i) nodes.push_back(i);
        for (std::uint32_t s = 0; s < model.springs.size(); ++s) springs.push_back(s);
        system.reserve(nodes.size(), springs.size());
        system.resize(nodes.size());
        system.assemble(model, h, {nodes, nodes, springs, 1});
    }
};

kernels::Field randomField(std::size_t count, std::size_t rows, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> value(-1, 1);
    kernels::Field f;
    f.resize(rows);
    for (auto* a : {&f.x, &f.y, &f.z})
        for (std::size_t k = 0; k < rows; ++k) (*a)[k] = k < count ? value(rng) : 0.0;
    return f;
}

double dot(const kernels::Field& a, const kernels::Field& b) {
    double sum = 0;
    for (std::size_t k = 0; k < a.x.size(); ++k) sum += a.x[k] * b.x[k] + a.y[k] * b.y[k] + a.z[k] * b.z[k];
    return sum;
}

// Conjugate gradients converge only with a symmetric positive definite preconditioner: the cycle's
// smoothing before and after its coarse correction must mirror each other, and its coarsest solve be exact.
TEST(MultilevelPreconditioner, IsSymmetricAndPositiveDefinite) {
    AssembledHeart heart(30'000, 20e-3);
    const BackwardEulerSystem& system = heart.system;
    MultilevelPreconditioner preconditioner;
    preconditioner.reserve(system.size(), system.slotCapacity());
    preconditioner.layOut(system.matrix(), system.size());
    preconditioner.assemble(system.matrix());
    ASSERT_GE(preconditioner.levels(), 3u);
    OwnedWorkerPool pool;
    const kernels::Field x = randomField(system.size(), system.rows(), 1),
                         y = randomField(system.size(), system.rows(), 2);
    kernels::Field bx, by;
    bx.resize(system.rows()), by.resize(system.rows());
    const kernels::Sums sx = preconditioner.apply(system.matrix(), system.inverseBlocks(), x, bx, pool);
    (void)preconditioner.apply(system.matrix(), system.inverseBlocks(), y, by, pool);
    EXPECT_NEAR(dot(y, bx), dot(x, by), 1e-9 * std::abs(dot(x, by))) << "yᵀBx = xᵀBy";
    EXPECT_GT(dot(x, bx), 0);
    EXPECT_NEAR(sx.rz, dot(x, bx), 1e-12 * dot(x, bx)) << "the sums it returns are x·Bx";
    EXPECT_NEAR(sx.r2, dot(x, x), 1e-12 * dot(x, x));
}

// Aggregates of a node and its neighbours shrink a surface mesh by about its neighbour count (6 to 8)
// level by level, down to a level small enough to factorise.
TEST(MultilevelPreconditioner, ShrinksASurfaceLevelByLevelToASmallCoarsestLevel) {
    AssembledHeart heart(100'000, 1e-3);
    MultilevelPreconditioner preconditioner;
    preconditioner.reserve(heart.system.size(), heart.system.slotCapacity());
    preconditioner.layOut(heart.system.matrix(), heart.system.size());
    ASSERT_GE(preconditioner.levels(), 4u);
    for (std::size_t level = 1; level < preconditioner.levels(); ++level) {
        const double ratio =
            static_cast<double>(preconditioner.rowsOf(level - 1)) / static_cast<double>(preconditioner.rowsOf(level));
        EXPECT_GT(ratio, 5) << "level " << level << ": " << preconditioner.rowsOf(level) << " rows";
    }
    EXPECT_LE(preconditioner.rowsOf(preconditioner.levels() - 1), MultilevelPreconditioner::kDenseRows);
}

/// Steps the 30,000 heart pressed for 20 steps of 20 ms from rest with one preconditioner, to a tight
/// tolerance; returns the model and the iterations.
MassSpringModel pressedWith(Preconditioner preconditioner, long& iterations, long& multilevelSolves) {
    const mesh::SurfaceMesh mesh = heartOf(30'000);
    MassSpringModel model = buildModel(mesh, Material{});
    Stepper stepper(Scheme::BackwardEuler);
    stepper.setSolverSettings(
        {.tolerance = 1e-8, .forceTolerance_N = 0, .maxIterations = 2000, .preconditioner = preconditioner});
    iterations = multilevelSolves = 0;
    for (int step = 0; step < 20; ++step) {
        test::pressFrontWithTool(model, mesh, std::min(20 * step, 200));  // pressed 3 mm in, and held
        const StepResult r = stepper.step(model, 20e-3);
        EXPECT_TRUE(r.finite && r.solve.converged) << "step " << step;
        iterations += r.solve.iterations;
        multilevelSolves += r.solve.multilevel;
    }
    return model;
}

// At 20 ms steps on the 30,000 heart the springs outweigh the nodes' mass by far, the regime of the
// multi-rate physics on fine meshes: the multilevel solve reaches the block-Jacobi solve's answer in
// under half its iterations (342 against 863 over the press, to 1e-8; on finer meshes the gap grows,
// 12 against 156 on the whole 1,000,000 heart to 1e-4).
TEST(MultilevelPreconditioner, SolvesAStiffStepInUnderHalfBlockJacobisIterations) {
    long jacobiIterations = 0, multilevelIterations = 0, jacobiMultilevel = 0, multilevelSolves = 0;
    const MassSpringModel jacobi = pressedWith(Preconditioner::BlockJacobi, jacobiIterations, jacobiMultilevel);
    const MassSpringModel multilevel = pressedWith(Preconditioner::Multilevel, multilevelIterations, multilevelSolves);
    EXPECT_EQ(jacobiMultilevel, 0);
    EXPECT_EQ(multilevelSolves, 20);
    EXPECT_LT(2 * multilevelIterations, jacobiIterations)
        << multilevelIterations << " multilevel iterations against " << jacobiIterations;
    const double moved = maxDisplacement(jacobi);
    ASSERT_GT(moved, 1e-3);
    double worst = 0;
    for (std::size_t i = 0; i < jacobi.nodes.size(); ++i)
        worst = std::max(worst, (jacobi.nodes.position[i] - multilevel.nodes.position[i]).norm());
    EXPECT_LT(worst, 1e-6 * moved) << "the same solution: " << worst << " m apart in a press of " << moved << " m";
}

// A pinned node's unknown stays zero under the multilevel cycle too: its row is left out of every level,
// so the coarse corrections of its neighbours' aggregates do not move it.
TEST(MultilevelPreconditioner, LeavesPinnedNodesWhereTheyAre) {
    const mesh::SurfaceMesh mesh = heartOf(9714);
    MassSpringModel model = buildModel(mesh, Material{});
    std::vector<std::uint32_t> pinned;
    for (std::uint32_t i = 0; i < model.nodes.size(); i += 7) {
        model.nodes.inverseMass[i] = 0;
        pinned.push_back(i);
    }
    const MassSpringModel start = model;
    Stepper stepper(Scheme::BackwardEuler);
    stepper.setSolverSettings({.preconditioner = Preconditioner::Multilevel});
    for (int step = 0; step < 50; ++step) {
        test::pressFrontWithTool(model, mesh, std::min(10 * step, 200));
        ASSERT_TRUE(stepper.step(model, 10e-3).finite);
    }
    EXPECT_GT(maxDisplacement(model), 1e-4);
    for (std::uint32_t i : pinned) ASSERT_EQ(model.nodes.position[i], start.nodes.position[i]) << "node " << i;
}

// Auto keeps block-Jacobi while its solves are short, and tries the multilevel cycle after one over a
// large region needs more than kJacobiIterationsForMultilevel iterations: a 50 ms step (the multi-rate
// physics' longest) of the jostled 30,000 heart, one Newton iteration solved to 1e-8, does.
TEST(MultilevelPreconditioner, AutoSwitchesToItAfterALongBlockJacobiSolve) {
    AssembledHeart heart(30'000, 50e-3);
    Stepper stepper(Scheme::BackwardEuler);
    stepper.setSolverSettings(
        {.tolerance = 1e-8, .forceTolerance_N = 0, .maxIterations = 200, .maxNewtonIterations = 1});
    const StepResult first = stepper.step(heart.model, 50e-3);
    EXPECT_FALSE(first.solve.multilevel);
    ASSERT_GT(first.solve.iterations, kJacobiIterationsForMultilevel);
    const StepResult second = stepper.step(heart.model, 50e-3);
    EXPECT_TRUE(second.solve.multilevel) << first.solve.iterations << " iterations, " << first.solve.newtonIterations
                                         << " Newton iterations at the first step";
    // It keeps the cycle where a multilevel solve costs less than the block-Jacobi one did, and goes back
    // where it does not.
    const bool pays = kMultilevelIterationCost * second.solve.iterations < first.solve.iterations;
    const StepResult third = stepper.step(heart.model, 50e-3);
    EXPECT_EQ(third.solve.multilevel, pays)
        << second.solve.iterations << " multilevel iterations against " << first.solve.iterations;
    // Where block-Jacobi stopped at its cap, the cycle stays whatever it costs: converged solves come first.
    AssembledHeart capped(30'000, 50e-3);
    Stepper cappedStepper(Scheme::BackwardEuler);
    cappedStepper.setSolverSettings(
        {.tolerance = 1e-8, .forceTolerance_N = 0, .maxIterations = 20, .maxNewtonIterations = 1});
    ASSERT_FALSE(cappedStepper.step(capped.model, 50e-3).solve.converged);
    for (int step = 0; step < 3; ++step) EXPECT_TRUE(cappedStepper.step(capped.model, 50e-3).solve.multilevel);
    // The small heart's short solves at 1 ms steps never take it.
    AssembledHeart small(1619, 1e-3);
    Stepper smallStepper(Scheme::BackwardEuler);
    for (int step = 0; step < 20; ++step) EXPECT_FALSE(smallStepper.step(small.model, 1e-3).solve.multilevel);
}

}  // namespace
}  // namespace hapticut::physics
