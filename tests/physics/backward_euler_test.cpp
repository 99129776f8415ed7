// The implicit scheme (linearised backward Euler, solved by conjugate gradients) against its closed
// form, its convergence order, RK4 at small steps and the static solution; its stability far beyond
// the explicit schemes' limits; and the choice Auto makes.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"
#include "hapticut/physics/spring_forces.h"
#include "test_support.h"

namespace hapticut::physics {
namespace {

constexpr SolverSettings kTight{.tolerance = 1e-12, .forceTolerance_N = 0, .maxIterations = kMaxSolverIterations};

mesh::SurfaceMesh heartMesh(int triangles) {
    mesh::procedural::HeartOptions options;
    options.triangles = triangles;
    return mesh::procedural::makeHeart(options);
}

// For x'' = -w2 x - c x', a backward-Euler step is [x; v] <- (I - h A)^-1 [x; v] with A = [0 1; -w2 -c].
// The system is linear, so the one Newton step of the linearised scheme must be the exact implicit step.
TEST(BackwardEuler, IsTheExactImplicitStepOnALinearOscillator) {
    const double m = 0.01, k = 40, c = 0.2, x0 = 0.005, h = 2e-3;
    MassSpringModel model = test::oscillator(m, k, c, x0);
    Stepper stepper(Scheme::BackwardEuler);
    stepper.setSolverSettings(kTight);
    Eigen::Matrix2d a;
    a << 0, 1, -k / m, -c / m;
    const Eigen::Matrix2d update = (Eigen::Matrix2d::Identity() - h * a).inverse();
    Eigen::Vector2d expected(x0, 0);
    for (int i = 0; i < 200; ++i) {
        (void)stepper.step(model, h);
        expected = update * expected;
        ASSERT_NEAR(model.nodes.position[0].x(), expected(0), 1e-12 * x0) << "step " << i;
        ASSERT_NEAR(model.nodes.velocity[0].x(), expected(1), 1e-12 * x0 * std::sqrt(k / m)) << "step " << i;
    }
}

double oscillatorErrorAtOneSecond(double dt_s) {
    MassSpringModel model = test::oscillator(1, 100, 0, 0.01);
    Stepper stepper(Scheme::BackwardEuler);
    stepper.setSolverSettings(kTight);
    for (long i = 0, steps = std::lround(1 / dt_s); i < steps; ++i) (void)stepper.step(model, dt_s);
    return std::abs(model.nodes.position[0].x() - 0.01 * std::cos(10.0));
}

TEST(BackwardEuler, ConvergesAtFirstOrder) {
    const double e1 = oscillatorErrorAtOneSecond(1e-3), e2 = oscillatorErrorAtOneSecond(5e-4);
    EXPECT_NEAR(std::log2(e1 / e2), 1, 0.1) << "errors " << e1 << ", " << e2;
}

/// The heart pressed by the tool for `duration_s`, stepped at dt_s by `scheme`.
MassSpringModel pressedHeart(const mesh::SurfaceMesh& mesh, Scheme scheme, double dt_s, double duration_s) {
    MassSpringModel model = buildModel(mesh, Material{});
    Stepper stepper(scheme);
    stepper.setSolverSettings(kTight);
    const long steps = std::lround(duration_s / dt_s);
    for (long i = 0; i < steps; ++i) {
        test::pressFrontWithTool(model, mesh, static_cast<int>(static_cast<double>(i) * dt_s * 1000));
        EXPECT_TRUE(stepper.step(model, dt_s).finite);
    }
    return model;
}

double largestDifference(const MassSpringModel& a, const MassSpringModel& b) {
    double worst = 0;
    for (std::size_t i = 0; i < a.nodes.size(); ++i)
        worst = std::max(worst, (a.nodes.position[i] - b.nodes.position[i]).norm());
    return worst;
}

// On the nonlinear heart pressed by a tool, the scheme approaches RK4 at small steps, and halving the
// step halves the difference: first order on the real model, not only on the oscillator.
TEST(BackwardEuler, AgreesWithRK4AtSmallStepsOnThePressedHeart) {
    const mesh::SurfaceMesh mesh = heartMesh(500);
    const double duration = 0.06;
    const MassSpringModel reference = pressedHeart(mesh, Scheme::RungeKutta4, 1e-5, duration);
    const double displacement = maxDisplacement(reference);
    ASSERT_GT(displacement, 3e-4) << "the press must really deform the tissue";
    const double coarse = largestDifference(pressedHeart(mesh, Scheme::BackwardEuler, 2e-5, duration), reference);
    const double fine = largestDifference(pressedHeart(mesh, Scheme::BackwardEuler, 1e-5, duration), reference);
    EXPECT_LT(fine, 0.01 * displacement) << "difference " << fine << " m in a press of " << displacement << " m";
    EXPECT_NEAR(std::log2(coarse / fine), 1, 0.15) << "differences " << coarse << ", " << fine;
}

// Without any damping the scheme still loses energy: backward Euler's numerical dissipation, which is
// what keeps it stable at any step.
TEST(BackwardEuler, DissipatesEnergyWithoutPhysicalDamping) {
    Material undamped;
    undamped.structuralDamping_Ns = 0;
    undamped.positioningDamping_Ns_per_m3 = 0;
    MassSpringModel model = buildModel(heartMesh(500), undamped);
    model.snapDistance_m = 0;
    for (std::size_t i = 0; i < model.nodes.size(); ++i) model.nodes.position[i] += test::wobble(i, 1e-3);
    Stepper stepper(Scheme::BackwardEuler);
    stepper.setSolverSettings(kTight);
    const double e0 = kineticEnergy(model) + potentialEnergy(model);
    double previous = e0;
    for (int i = 0; i < 200; ++i) {
        (void)stepper.step(model, 1e-3);
        const double e = kineticEnergy(model) + potentialEnergy(model);
        ASSERT_LT(e, previous) << "step " << i;
        previous = e;
    }
    EXPECT_LT(previous, 0.01 * e0);
}

// Static equilibrium by Newton's method on the spring forces, with a central-difference Jacobian: an
// independent answer for where a loaded model comes to rest.
std::vector<Vec3> staticSolution(MassSpringModel model) {
    const std::size_t n = model.nodes.size();
    auto force = [&](const Eigen::VectorXd& q) {
        std::vector<Vec3> x(n), v(n, Vec3::Zero()), a(n);
        for (std::size_t i = 0; i < n; ++i) x[i] = q.segment<3>(3 * i);
        computeAccelerations(model, x, v, a);
        Eigen::VectorXd f(3 * n);
        for (std::size_t i = 0; i < n; ++i) f.segment<3>(3 * i) = model.nodes.mass[i] * a[i];
        return f;
    };
    Eigen::VectorXd q(3 * n);
    for (std::size_t i = 0; i < n; ++i) q.segment<3>(3 * i) = model.nodes.position[i];
    for (int iteration = 0; iteration < 30; ++iteration) {
        const Eigen::VectorXd f = force(q);
        if (f.norm() < 1e-14) break;
        Eigen::MatrixXd jacobian(3 * n, 3 * n);
        const double e = 1e-7;
        for (std::size_t j = 0; j < 3 * n; ++j) {
            Eigen::VectorXd plus = q, minus = q;
            plus(j) += e;
            minus(j) -= e;
            jacobian.col(j) = (force(plus) - force(minus)) / (2 * e);
        }
        q -= jacobian.partialPivLu().solve(f);
    }
    std::vector<Vec3> x(n);
    for (std::size_t i = 0; i < n; ++i) x[i] = q.segment<3>(3 * i);
    return x;
}

TEST(BackwardEuler, ALoadedModelSettlesOnTheStaticSolution) {
    MassSpringModel model = buildModel(mesh::procedural::makeSphere(Vec3::Zero(), 0.03, 12, 8), Material{});
    model.snapDistance_m = 0;
    model.nodes.externalForce[3] = Vec3(0, 0, -1.5);
    model.nodes.externalForce[20] = Vec3(1.0, 0.6, 0);
    model.gravity_m_per_s2 = Vec3(0, -9.81, 0);
    const std::vector<Vec3> expected = staticSolution(model);
    double displacement = 0;
    for (std::size_t i = 0; i < expected.size(); ++i)
        displacement = std::max(displacement, (expected[i] - model.nodes.restPosition[i]).norm());
    ASSERT_GT(displacement, 1e-3) << "the load must really deform the model";

    Stepper stepper(Scheme::BackwardEuler);
    stepper.setSolverSettings(kTight);
    for (int i = 0; i < 400; ++i) ASSERT_TRUE(stepper.step(model, 10e-3).finite);
    double worst = 0;
    for (std::size_t i = 0; i < expected.size(); ++i)
        worst = std::max(worst, (model.nodes.position[i] - expected[i]).norm());
    EXPECT_LT(worst, 1e-6 * displacement) << "off by " << worst << " m in a deformation of " << displacement << " m";
}

// The 100,000-triangle heart, where RK4 needs a step 500 times smaller, pressed by the tool and
// stepped at 10 ms: bounded throughout, and back at rest after the tool lifts.
TEST(BackwardEuler, StaysBoundedAtTenMillisecondStepsOnTheHundredThousandTriangleHeart) {
    const mesh::SurfaceMesh mesh = heartMesh(100'000);
    MassSpringModel model = buildModel(mesh, Material{});
    EXPECT_LT(stableTimeStep(model, Scheme::RungeKutta4, 400), 2e-5);
    Stepper stepper(Scheme::BackwardEuler);
    double largest = 0;
    for (int step = 0; step < 100; ++step) {
        test::pressFrontWithTool(model, mesh, step * 10);
        const StepResult r = stepper.step(model, 10e-3);
        ASSERT_TRUE(r.finite) << "step " << step;
        largest = std::max(largest, maxDisplacement(model));
    }
    EXPECT_GT(largest, 1e-3) << "the press must really deform the tissue";
    EXPECT_LT(largest, 0.01) << "a 3 mm press moves nothing a centimetre";
    EXPECT_LT(maxDisplacement(model), 1e-5) << "back at rest 0.7 s after the tool lifted";
}

// A coupling a hundred times stiffer than the default, at which RK4 would need substeps on every
// node the tool may touch, at one step per millisecond.
TEST(BackwardEuler, TakesAStiffToolCouplingAtOneStepPerMillisecond) {
    const mesh::SurfaceMesh mesh = heartMesh(1619);
    MassSpringModel model = buildModel(mesh, Material{});
    EXPECT_LT(stableTimeStep(model, Scheme::RungeKutta4, 40'000), 0.5e-3);
    Stepper stepper(Scheme::BackwardEuler);
    double force = 0;
    for (int step = 0; step < 200; ++step) {
        test::pressFrontWithTool(model, mesh, step);
        model.tools[0].stiffness_N_per_m = 40'000;
        model.tools[0].maxForce_N = 1e9;
        ASSERT_TRUE(stepper.step(model, 1e-3).finite) << "step " << step;
        force = model.tools[0].forceOnTool(model.nodes.position).norm();
        ASSERT_LT(maxDisplacement(model), 0.01) << "step " << step;
    }
    EXPECT_GT(force, 0.1) << "the tool really presses";
}

// A scalpel pressed at its clamped force (3.3 N) on tissue a cut has just freed: a node of a milligram
// held by springs a thousand times weaker than the organ's, under the whole load, the device 10 mm in.
// Each step carries the node at most to the device, never beyond it, with Newton's corrections or
// without (the one linearised step, or corrections cut short to keep pace). With the clamped force left
// out of the matrix as a constant, the linearised step threw such a node metres past the blade.
TEST(BackwardEuler, AClampedToolNeverCarriesTheTissuePastTheDevice) {
    const mesh::SurfaceMesh mesh = heartMesh(1619);
    for (int newtonIterations : {1, SolverSettings{}.maxNewtonIterations}) {
        MassSpringModel model = buildModel(mesh, Material{});
        const std::uint32_t node = 700;
        model.nodes.mass[node] = 1e-6, model.nodes.inverseMass[node] = 1e6;
        model.nodes.anchorStiffness[node] = model.nodes.anchorDamping[node] = 0;
        for (std::size_t k = 0; k < model.springs.size(); ++k)
            if (model.springs.a[k] == node || model.springs.b[k] == node) model.springs.stiffness[k] *= 1e-3;
        const Vec3 outward = model.nodes.restPosition[node].normalized();
        PointSpring& tool = model.tools[0];
        tool.active = true;
        tool.count = 1, tool.nodes[0] = node, tool.weights[0] = 1, tool.spread = true;
        tool.anchor_m = model.nodes.restPosition[node] - 0.01 * outward;
        tool.stiffness_N_per_m = 400;  // 4 N asked for at first: clamped
        tool.maxForce_N = 3.3;
        tool.normal = outward;
        Stepper stepper(Scheme::BackwardEuler);
        stepper.setSolverSettings({.maxNewtonIterations = newtonIterations});
        double deepest = 0;
        for (int step = 0; step < 50; ++step) {
            ASSERT_TRUE(stepper.step(model, 4e-3).finite);
            const double pastDevice = (tool.anchor_m - model.nodes.position[node]).dot(outward);
            ASSERT_LT(pastDevice, 1e-4) << "Newton iterations " << newtonIterations << ", step " << step << ": "
                                        << pastDevice << " m past the device";
            deepest = std::max(deepest, 0.01 - pastDevice);
        }
        EXPECT_GT(deepest, 0.009) << "the tool really pushes the node in, to within a millimetre of the device";
    }
}

TEST(BackwardEuler, OnlyTheActiveRegionMatchesTheFullSolve) {
    const mesh::SurfaceMesh mesh = heartMesh(9714);
    MassSpringModel full = buildModel(mesh, Material{}), local = full;
    Stepper fullStepper(Scheme::BackwardEuler), localStepper(Scheme::BackwardEuler);
    localStepper.setActiveRegion(true);
    double worst = 0, largest = 0;
    std::size_t largestRegion = 0;
    for (int step = 0; step < 600; ++step) {
        test::pressFrontWithTool(full, mesh, step);
        test::pressFrontWithTool(local, mesh, step);
        ASSERT_TRUE(fullStepper.step(full, 1e-3).finite);
        ASSERT_TRUE(localStepper.step(local, 1e-3).finite);
        largestRegion = std::max(largestRegion, localStepper.awakeCount());
        largest = std::max(largest, maxDisplacement(full));
        worst = std::max(worst, largestDifference(full, local));
    }
    EXPECT_GT(largest, 1e-3);
    EXPECT_LT(worst, 0.01 * largest) << "worst difference " << worst << " m";
    EXPECT_LT(largestRegion, full.nodes.size() / 3) << "the region stays local";
    EXPECT_EQ(localStepper.awakeCount(), 0u) << "asleep again 0.3 s after the tool left";
}

// 1 N on one node of a fine mesh at 5 ms steps: springs at their rest length have no transverse
// stiffness in one linearisation, so a single Newton step throws the node far past where it settles.
// Newton's corrections keep the largest displacement near the settled one, as RK4 does at small steps.
TEST(BackwardEuler, NewtonCorrectionsKeepAPointLoadFromOvershooting) {
    const mesh::SurfaceMesh mesh = heartMesh(9714);
    auto largestDisplacement = [&](int newtonIterations, double& settled) {
        MassSpringModel model = buildModel(mesh, Material{});
        Stepper stepper(Scheme::BackwardEuler);
        stepper.setSolverSettings({.maxNewtonIterations = newtonIterations});
        const std::uint32_t node = 4330;
        model.nodes.externalForce[node] = Vec3(0, 0, -1);
        double largest = 0;
        int corrected = 0;
        for (int step = 0; step < 60; ++step) {
            const StepResult r = stepper.step(model, 5e-3);
            EXPECT_TRUE(r.finite);
            corrected += r.solve.newtonIterations > 1;
            largest = std::max(largest, maxDisplacement(model));
        }
        settled = (model.nodes.position[node] - model.nodes.restPosition[node]).norm();
        if (newtonIterations > 1) {
            EXPECT_GT(corrected, 0);
        }
        return largest;
    };
    double settledOnce = 0, settled = 0;
    const double once = largestDisplacement(1, settledOnce);
    const double corrected = largestDisplacement(4, settled);
    EXPECT_GT(once, 1.3 * settledOnce) << "one linearisation overshoots: " << once << " m against " << settledOnce;
    EXPECT_LT(corrected, 1.1 * settled) << corrected << " m against " << settled << " m settled";
    EXPECT_NEAR(settled, settledOnce, 1e-3 * settled) << "both settle where the load holds the node";
}

TEST(BackwardEuler, ReportsIterationsAndResidualAndStopsAtTheCap) {
    const mesh::SurfaceMesh mesh = heartMesh(1619);
    MassSpringModel capped = buildModel(mesh, Material{}), converged = capped;
    Stepper cappedStepper(Scheme::BackwardEuler), convergedStepper(Scheme::BackwardEuler);
    cappedStepper.setSolverSettings({.tolerance = 1e-10, .maxIterations = 2, .maxNewtonIterations = 1});
    convergedStepper.setSolverSettings({.tolerance = 1e-6, .forceTolerance_N = 0, .maxIterations = 1000});
    test::pressFrontWithTool(capped, mesh, 20);
    test::pressFrontWithTool(converged, mesh, 20);
    const SolveReport a = cappedStepper.step(capped, 1e-3).solve;
    EXPECT_EQ(a.iterations, 2);
    EXPECT_FALSE(a.converged);
    EXPECT_GT(a.relativeResidual, 1e-10);
    const SolveReport b = convergedStepper.step(converged, 1e-3).solve;
    EXPECT_TRUE(b.converged);
    EXPECT_GT(b.iterations, 2);
    EXPECT_LE(b.relativeResidual, 1e-6);
}

// Keeping pace with the wall clock, a step takes a further Newton iteration only while it still fits in
// its share of the time the step simulates: none at all when the share is tiny, every one the settings
// allow when it is vast. The point load above at 5 ms steps, which wants corrections.
TEST(BackwardEuler, KeepingPaceCutsNewtonsCorrectionsShortOnlyWhenTheyDoNotFit) {
    const mesh::SurfaceMesh mesh = heartMesh(9714);
    struct Counts {
        int corrected = 0, cutShort = 0;
    };
    auto run = [&](double share) {
        MassSpringModel model = buildModel(mesh, Material{});
        Stepper stepper(Scheme::BackwardEuler);
        stepper.keepPace(share);
        model.nodes.externalForce[4330] = Vec3(0, 0, -1);
        Counts counts;
        for (int step = 0; step < 20; ++step) {
            const SolveReport r = stepper.step(model, 5e-3).solve;
            counts.corrected += r.newtonIterations > 1;
            counts.cutShort += r.newtonCutShort;
        }
        return counts;
    };
    const Counts off = run(0), vast = run(1e9), tiny = run(1e-9);
    EXPECT_GT(off.corrected, 0);
    EXPECT_EQ(off.cutShort, 0);
    EXPECT_EQ(vast.corrected, off.corrected);
    EXPECT_EQ(vast.cutShort, 0);
    EXPECT_EQ(tiny.corrected, 0);
    EXPECT_GT(tiny.cutShort, 0);
}

// The last step's change of velocity is the next solve's start, scaled along its line to the point
// nearest the solution: where the tissue changes course (a release, a reset, ringing), the raw start was
// farther from the answer than zero, by up to five times on a scalpel stroke.
TEST(BackwardEuler, AWarmStartFromAnotherMotionCostsNoMoreThanAColdOne) {
    const mesh::SurfaceMesh mesh = heartMesh(9714);
    MassSpringModel model = buildModel(mesh, Material{});
    const SolverSettings settings{.forceTolerance_N = 0, .maxIterations = 1000, .maxNewtonIterations = 1};
    Stepper warm(Scheme::BackwardEuler);
    warm.setSolverSettings(settings);
    // The front half of the heart pushed back with 1 N in all, then let go at rest with a thousandth of it.
    std::vector<std::uint32_t> front;
    for (std::uint32_t i = 0; i < model.nodes.size(); ++i)
        if (model.nodes.restPosition[i].z() > 0) front.push_back(i);
    auto load = [&](double total_N) {
        for (std::uint32_t i : front)
            model.nodes.externalForce[i] = Vec3(0, 0, -total_N / static_cast<double>(front.size()));
    };
    load(1);
    for (int step = 0; step < 3; ++step) ASSERT_TRUE(warm.step(model, 5e-3).finite);
    model.nodes.position = model.nodes.restPosition;
    std::fill(model.nodes.velocity.begin(), model.nodes.velocity.end(), Vec3::Zero());
    load(1e-3);
    MassSpringModel same = model;
    Stepper cold(Scheme::BackwardEuler);
    cold.setSolverSettings(settings);
    const SolveReport fromTheLastStep = warm.step(model, 5e-3).solve, fromZero = cold.step(same, 5e-3).solve;
    ASSERT_TRUE(fromTheLastStep.converged && fromZero.converged);
    EXPECT_LE(fromTheLastStep.iterations, fromZero.iterations);
}

// Tissue near rest has a right-hand side so small that the relative tolerance of it asks for
// nanonewtons: the solve stops once no node's residual is above forceTolerance_N as a force.
TEST(BackwardEuler, ASolveStopsOnceItsResidualForceIsBelowTheForceTolerance) {
    const mesh::SurfaceMesh mesh = heartMesh(1619);
    auto solveWith = [&](double forceTolerance_N) {
        MassSpringModel model = buildModel(mesh, Material{});
        Stepper stepper(Scheme::BackwardEuler);
        stepper.setSolverSettings({.forceTolerance_N = forceTolerance_N, .maxIterations = 1000});
        model.nodes.externalForce[400] = Vec3(0, 0, 1e-4);  // a tenth of a millinewton
        return stepper.step(model, 1e-3).solve;
    };
    const SolveReport floored = solveWith(1e-6), relative = solveWith(0);
    EXPECT_TRUE(floored.converged && relative.converged);
    EXPECT_LT(floored.iterations, relative.iterations);
    // |b| = h · 1e-4 N; the floor stops at 1e-6 N · h, a hundredth of it, where 1e-4 of it is asked otherwise.
    EXPECT_LE(floored.relativeResidual, 1e-2);
    EXPECT_GT(floored.relativeResidual, 1e-4);
    EXPECT_LE(relative.relativeResidual, 1e-4);
}

// The force tolerance holds node by node, not on the whole residual, whose norm grows with the number
// of nodes: 10 µN on each of the 9,714 heart's nodes, and the solve stops once each node's residual is
// under 1 µN, though the whole residual's norm is still above it.
TEST(BackwardEuler, TheForceToleranceHoldsNodeByNode) {
    const MassSpringModel heart = buildModel(heartMesh(9714), Material{});
    constexpr double kLoad_N = 1e-5, kTolerance_N = 1e-6;
    auto solveWith = [&](double forceTolerance_N) {
        MassSpringModel model = heart;
        Stepper stepper(Scheme::BackwardEuler);
        stepper.setSolverSettings({.tolerance = 1e-12, .forceTolerance_N = forceTolerance_N, .maxIterations = 1000});
        for (Vec3& f : model.nodes.externalForce) f = Vec3(0, 0, kLoad_N);
        return stepper.step(model, 1e-3).solve;
    };
    const SolveReport floored = solveWith(kTolerance_N), full = solveWith(0);
    ASSERT_TRUE(floored.converged && full.converged);
    EXPECT_LT(floored.iterations, full.iterations);
    // From rest b = h f, so the residual's norm as a force is relativeResidual · |f|.
    const double nodes = static_cast<double>(heart.nodes.size());
    const double residual_N = floored.relativeResidual * kLoad_N * std::sqrt(nodes);
    EXPECT_GT(residual_N, kTolerance_N) << "a tolerance on the whole residual would have gone on";
    EXPECT_LE(residual_N, kTolerance_N * std::sqrt(nodes)) << "no node above the tolerance bounds the whole";
}

TEST(Auto, KeepsRK4WhereOneStepIsStableAndTakesTheImplicitSchemeElsewhere) {
    const MassSpringModel thesisSized = buildModel(heartMesh(1619), Material{});
    const MassSpringModel finer = buildModel(heartMesh(9714), Material{});
    EXPECT_EQ(resolveScheme(Scheme::Auto, thesisSized, 1e-3, 400), Scheme::RungeKutta4);
    EXPECT_EQ(resolveScheme(Scheme::Auto, finer, 1e-3, 400), Scheme::BackwardEuler);
    EXPECT_EQ(resolveScheme(Scheme::Auto, finer, 1e-5, 400), Scheme::RungeKutta4);
    EXPECT_EQ(resolveScheme(Scheme::Midpoint, finer, 1e-3, 400), Scheme::Midpoint);
    Stepper stepper(Scheme::Auto);
    MassSpringModel model = finer;
    (void)stepper.step(model, 1e-3);
    EXPECT_EQ(stepper.scheme(), Scheme::BackwardEuler);
}

}  // namespace
}  // namespace hapticut::physics
