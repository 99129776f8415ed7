// Integrators against closed-form solutions, convergence order, conservation laws and stability.
#include <gtest/gtest.h>

#include <cmath>

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"
#include "hapticut/physics/solver_kernels.h"
#include "hapticut/physics/spring_forces.h"
#include "test_support.h"

namespace hapticut::physics {
namespace {

constexpr Scheme kAllSchemes[] = {Scheme::ExplicitEuler, Scheme::Midpoint, Scheme::RungeKutta4,
                                  Scheme::SymplecticEuler};

double positionAt(MassSpringModel model, Scheme scheme, double dt_s, double t_end_s) {
    Stepper stepper(scheme);
    stepper.setAutoSubstep(false);
    const long steps = std::lround(t_end_s / dt_s);
    for (long i = 0; i < steps; ++i) (void)stepper.step(model, dt_s);
    return model.nodes.position[0].x();
}

// Undamped oscillator: m = 1 kg, k = 100 N/m, x(0) = 0.01 m, v(0) = 0, so x(t) = 0.01 cos(10 t).
// Halving dt divides the error at t = 1 s by 2^order.
double oscillatorError(Scheme scheme, double dt_s) {
    return std::abs(positionAt(test::oscillator(1, 100, 0, 0.01), scheme, dt_s, 1.0) - 0.01 * std::cos(10.0));
}

TEST(Integrators, ConvergeAtTheirTheoreticalOrder) {
    const struct {
        Scheme scheme;
        double dt_s, order;
    } cases[] = {{Scheme::ExplicitEuler, 1e-3, 1},
                 {Scheme::SymplecticEuler, 1e-3, 1},
                 {Scheme::Midpoint, 1e-3, 2},
                 {Scheme::RungeKutta4, 5e-3, 4}};
    for (const auto& c : cases) {
        const double e1 = oscillatorError(c.scheme, c.dt_s), e2 = oscillatorError(c.scheme, c.dt_s / 2);
        EXPECT_NEAR(std::log2(e1 / e2), c.order, 0.15) << schemeName(c.scheme) << ": errors " << e1 << ", " << e2;
    }
}

// Classic RK4 written out from computeAccelerations, its stages' sums in the stepper's order: the
// stepper's passes over every node, folded into one a stage, must give its bits exactly under every
// instruction set the springs' kernel has, with a tool pressing, gravity and an external force in play.
TEST(Integrators, RungeKutta4OverEveryNodeIsTheTextbookSchemeToTheBit) {
    const mesh::SurfaceMesh mesh = mesh::procedural::makeHeart({});
    MassSpringModel model = buildModel(mesh, Material{});
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
        model.nodes.position[i] += test::wobble(i, 5e-4);
        model.nodes.velocity[i] = test::wobble(3 * i + 1, 0.05);
    }
    model.gravity_m_per_s2 = Vec3(0, -9.81, 0);
    model.nodes.externalForce[7] = Vec3(0.1, -0.2, 0.3);
    test::pressFrontWithTool(model, mesh, 100);
    ASSERT_TRUE(model.tools[0].active);

    const double h = 2e-4, half = 0.5 * h, sixth = h / 6;
    const std::vector<Vec3> x = model.nodes.position, v = model.nodes.velocity;
    std::vector<Vec3> a(x.size()), xs(x.size()), vs(x.size()), xEnd = x, vEnd = v;
    computeAccelerations(model, x, v, a);
    for (std::size_t i = 0; i < x.size(); ++i) {
        xs[i] = x[i] + half * v[i], vs[i] = v[i] + half * a[i];
        xEnd[i] += sixth * v[i], vEnd[i] += sixth * a[i];
    }
    for (int stage = 2; stage <= 4; ++stage) {
        computeAccelerations(model, xs, vs, a);
        const double weight = stage == 4 ? sixth : 2 * sixth, next = stage == 3 ? h : half;
        for (std::size_t i = 0; i < x.size(); ++i) {
            xEnd[i] += weight * vs[i], vEnd[i] += weight * a[i];
            xs[i] = x[i] + next * vs[i], vs[i] = v[i] + next * a[i];
        }
    }

    for (const char* target : kernels::supportedTargets()) {
        ASSERT_TRUE(kernels::forceTarget(target)) << target;
        MassSpringModel stepped = model;
        Stepper stepper(Scheme::RungeKutta4);
        stepper.setAutoSubstep(false);
        ASSERT_TRUE(stepper.step(stepped, h).finite) << target;
        std::size_t differing = 0;
        for (std::size_t i = 0; i < x.size(); ++i)
            for (int c = 0; c < 3; ++c)
                differing += stepped.nodes.position[i][c] != xEnd[i][c] || stepped.nodes.velocity[i][c] != vEnd[i][c];
        EXPECT_EQ(differing, 0u) << target << ": of " << 6 * x.size() << " coordinates";
    }
    EXPECT_TRUE(kernels::forceTarget(nullptr));
    EXPECT_GT((xEnd[7] - x[7]).norm(), 1e-6) << "the step must move the nodes";
}

// A damped spring (m = 0.01 kg, k = 40 N/m, c = 0.2 N·s/m: γ = 10/s, ω = 63.2 rad/s, underdamped):
// x(t) = x0 e^{-γt} (cos ω_d t + γ/ω_d sin ω_d t).
TEST(Integrators, DampedSpringMatchesAnalyticSolution) {
    const double m = 0.01, k = 40, c = 0.2, x0 = 0.005;
    const double gamma = c / (2 * m), wd = std::sqrt(k / m - gamma * gamma);
    for (double t : {0.05, 0.2, 0.5}) {
        const double exact = x0 * std::exp(-gamma * t) * (std::cos(wd * t) + gamma / wd * std::sin(wd * t));
        EXPECT_NEAR(positionAt(test::oscillator(m, k, c, x0), Scheme::RungeKutta4, 1e-3, t), exact, 1e-9)
            << "t = " << t;
        EXPECT_NEAR(positionAt(test::oscillator(m, k, c, x0), Scheme::Midpoint, 1e-4, t), exact, 1e-7) << "t = " << t;
        EXPECT_NEAR(positionAt(test::oscillator(m, k, c, x0), Scheme::ExplicitEuler, 1e-5, t), exact, 5e-6)
            << "t = " << t;
        EXPECT_NEAR(positionAt(test::oscillator(m, k, c, x0), Scheme::SymplecticEuler, 1e-5, t), exact, 5e-6)
            << "t = " << t;
    }
}

// A structural spring between a fixed node and a free one, stretched along x: the free node oscillates
// about the rest length with ω = sqrt(k/m), exactly as the oscillator above but through R3's formula.
TEST(Integrators, StructuralSpringOscillatesAboutItsRestLength) {
    MassSpringModel model = test::oscillator(0.01, 0, 0, 0);
    Nodes& n = model.nodes;
    n.position = {Vec3::Zero(), Vec3(0.012, 0, 0)};
    n.restPosition = n.position;
    n.velocity.assign(2, Vec3::Zero());
    n.externalForce.assign(2, Vec3::Zero());
    n.mass = {1, 0.01};
    n.inverseMass = {0, 100};  // node 0 is fixed
    n.anchorStiffness.assign(2, 0.0);
    n.anchorDamping.assign(2, 0.0);
    model.springs.a = {0};
    model.springs.b = {1};
    model.springs.restLength = {0.010};
    model.springs.stiffness = {40};
    model.springs.damping = {0};
    Stepper stepper(Scheme::RungeKutta4);
    const double w = std::sqrt(40 / 0.01);
    for (int i = 0; i < 300; ++i) (void)stepper.step(model, 1e-4);
    EXPECT_NEAR(n.position[1].x(), 0.010 + 0.002 * std::cos(w * 0.03), 1e-9);
    EXPECT_EQ(n.position[0], Vec3::Zero());
}

TEST(SymplecticEuler, EnergyStaysBounded) {
    // The energy error oscillates with amplitude about ω·dt/2 (0.5% here) instead of growing.
    MassSpringModel model = test::oscillator(1, 100, 0, 0.01);
    const double e0 = potentialEnergy(model);
    Stepper stepper(Scheme::SymplecticEuler);
    double worst = 0;
    for (int i = 0; i < 10'000; ++i) {
        (void)stepper.step(model, 1e-3);
        worst = std::max(worst, std::abs(kineticEnergy(model) + potentialEnergy(model) - e0) / e0);
    }
    EXPECT_LT(worst, 0.01);
    EXPECT_GT(worst, 1e-4);  // it is not exact either: this checks the measurement itself
}

MassSpringModel smallHeart(const Material& material = {}) {
    mesh::procedural::HeartOptions options;
    options.triangles = 500;
    return buildModel(mesh::procedural::makeHeart(options), material);
}

TEST(Integrators, ConserveLinearMomentumWithoutPositioningSprings) {
    Material free;
    free.positioningStiffness_N_per_m3 = 0;
    free.positioningDamping_Ns_per_m3 = 0;
    for (Scheme scheme : kAllSchemes) {
        MassSpringModel model = smallHeart(free);
        for (std::size_t i = 0; i < model.nodes.size(); ++i) {
            model.nodes.velocity[i] = test::wobble(i, 0.01);
            model.nodes.position[i] += test::wobble(i + 1000, 1e-4);
        }
        const Vec3 p0 = linearMomentum(model);
        Stepper stepper(scheme);
        for (int i = 0; i < 500; ++i) ASSERT_TRUE(stepper.step(model, 1e-3).finite);
        EXPECT_LT((linearMomentum(model) - p0).norm(), 1e-12 * (1 + p0.norm())) << schemeName(scheme);
        EXPECT_GT(maxDisplacement(model), 1e-3) << "the model drifted freely, so the springs were doing work";
    }
}

TEST(Integrators, DampingDissipatesEnergy) {
    for (Scheme scheme : kAllSchemes) {
        MassSpringModel model = smallHeart();
        for (std::size_t i = 0; i < model.nodes.size(); ++i) model.nodes.position[i] += test::wobble(i, 1e-3);
        Stepper stepper(scheme);
        const double e0 = kineticEnergy(model) + potentialEnergy(model);
        double previous = e0;
        for (int block = 0; block < 10; ++block) {
            for (int i = 0; i < 20; ++i) (void)stepper.step(model, 1e-3);
            const double e = kineticEnergy(model) + potentialEnergy(model);
            // Strictly falling, until the snap-back rule puts every node exactly at rest.
            EXPECT_TRUE(e < previous || e == 0)
                << schemeName(scheme) << " block " << block << ": " << e << " after " << previous;
            previous = e;
        }
        EXPECT_LT(previous, 0.01 * e0) << schemeName(scheme);
    }
}

TEST(Integrators, ModelReturnsToRestAfterReleasedForce) {
    for (Scheme scheme : kAllSchemes) {
        MassSpringModel model = smallHeart();
        Stepper stepper(scheme);
        model.nodes.externalForce[7] = Vec3(0, 0, -1);
        for (int i = 0; i < 200; ++i) (void)stepper.step(model, 1e-3);
        EXPECT_GT(maxDisplacement(model), 1e-3) << schemeName(scheme) << ": a 1 N press must indent the tissue";
        model.nodes.externalForce[7] = Vec3::Zero();
        for (int i = 0; i < 3000; ++i) (void)stepper.step(model, 1e-3);
        EXPECT_LT(maxDisplacement(model), 1e-6) << schemeName(scheme);
    }
}

TEST(Stability, DefaultMaterialRunsTheThesisSizedHeartAt1msWithAtMostTwoSubsteps) {
    // RK4 (the default), midpoint and explicit Euler take 1 ms steps as they are; symplectic Euler, whose
    // damped stability window is narrower, takes two substeps.
    const MassSpringModel model = buildModel(mesh::procedural::makeHeart({}), Material{});
    for (Scheme scheme : {Scheme::ExplicitEuler, Scheme::Midpoint, Scheme::RungeKutta4})
        EXPECT_GE(stableTimeStep(model, scheme), 1e-3) << schemeName(scheme);
    EXPECT_GE(stableTimeStep(model, Scheme::SymplecticEuler), 0.5e-3);
    // With the default 400 N/m haptic coupling counted on every node, RK4 still takes 1 ms steps.
    EXPECT_GE(stableTimeStep(model, Scheme::RungeKutta4, 400), 1e-3);
}

TEST(Stability, EstimateSeparatesStableFromUnstableSteps) {
    // Stepping at the estimate stays bounded; at three times the estimate the model blows up, so the
    // estimate is neither unsafe nor uselessly small.
    for (Scheme scheme : kAllSchemes) {
        MassSpringModel model = smallHeart();
        model.snapDistance_m = 0;
        const double dt = stableTimeStep(model, scheme);
        for (double factor : {1.0, 3.0}) {
            MassSpringModel m = model;
            for (std::size_t i = 0; i < m.nodes.size(); ++i) m.nodes.position[i] += test::wobble(i, 1e-4);
            Stepper stepper(scheme);
            stepper.setAutoSubstep(false);
            bool finite = true;
            for (int i = 0; i < 3000 && finite; ++i) finite = stepper.step(m, factor * dt).finite;
            const bool bounded = finite && maxDisplacement(m) < 1e-3;
            EXPECT_EQ(bounded, factor == 1.0) << schemeName(scheme) << " at " << factor << " x " << dt << " s";
        }
    }
}

TEST(Stepper, SubstepsAutomaticallyWhenTheStepIsTooLarge) {
    MassSpringModel model = smallHeart();
    Stepper stepper(Scheme::ExplicitEuler);
    stepper.prepare(model);
    const double stable = stepper.stableStep_s();
    EXPECT_EQ(stepper.substepsFor(0.5 * stable), 1);
    EXPECT_EQ(stepper.substepsFor(2.5 * stable), 3);
    model.nodes.position[3] += Vec3(1e-3, 0, 0);
    const StepResult r = stepper.step(model, 10 * stable);
    EXPECT_EQ(r.substeps, 10);
    EXPECT_TRUE(r.finite);
}

TEST(Stepper, NonFiniteStateIsDetectedAndRolledBack) {
    MassSpringModel model = smallHeart();
    Stepper stepper(Scheme::RungeKutta4);
    model.nodes.externalForce[5] = Vec3(std::nan(""), 0, 0);
    model.nodes.position[7] += Vec3(1e-4, 0, 0);  // a node away from rest, which a rollback must not move
    const std::vector<Vec3> before = model.nodes.position;
    const StepResult r = stepper.step(model, 1e-3);
    EXPECT_FALSE(r.finite);
    EXPECT_TRUE(allFinite(model));
    // Back where the step began, and still.
    EXPECT_EQ(model.nodes.position, before);
    for (const Vec3& v : model.nodes.velocity) EXPECT_EQ(v, Vec3::Zero());
    model.nodes.externalForce[5] = Vec3::Zero();
    EXPECT_TRUE(stepper.step(model, 1e-3).finite);
}

TEST(Material, SpreadsMassByAreaAndScalesSpringsByLength) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    const MassSpringModel model = buildModel(heart, Material{});
    EXPECT_NEAR(totalMass(model), 0.3, 1e-12);
    for (std::size_t i = 0; i < model.springs.size(); ++i)
        EXPECT_NEAR(model.springs.stiffness[i] * model.springs.restLength[i], Material{}.structuralStiffness_N, 1e-12);
    const mesh::io::ThesisPhysics thesis{.mass = 2,
                                         .structuralStiffness = 20,
                                         .structuralDamping = 2,
                                         .positioningStiffness = 5,
                                         .positioningDamping = 1};
    const MassSpringModel uniform = buildModel(heart, thesis);
    EXPECT_NEAR(totalMass(uniform), 2, 1e-12);
    EXPECT_EQ(uniform.nodes.mass.front(), uniform.nodes.mass.back());
    EXPECT_EQ(uniform.springs.stiffness.front(), 20);
}

}  // namespace
}  // namespace hapticut::physics

namespace hapticut::physics {
namespace {

TEST(PointSpring, TissueFeelsExactlyTheToolForceReversed) {
    MassSpringModel model = buildModel(mesh::procedural::makeHeart({}), Material{});
    for (Vec3& f : model.nodes.externalForce) f = Vec3::Zero();
    model.tools[0].active = true;
    model.tools[0].touchTriangle({3, 17, 40}, Vec3(0.2, 0.5, 0.3));
    model.tools[0].anchor_m = Vec3(0, 0, 0.02);
    model.tools[0].stiffness_N_per_m = 500;
    model.tools[0].maxForce_N = 3.3;
    // Accelerations times masses at rest (springs and anchors exert nothing) are the tool's reaction.
    std::vector<Vec3> a(model.nodes.size());
    computeAccelerations(model, model.nodes.position, model.nodes.velocity, a);
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0; i < a.size(); ++i) sum += model.nodes.mass[i] * a[i];
    const Vec3 f = model.tools[0].forceOnTool(model.nodes.position);
    EXPECT_LT((sum + f).norm(), 1e-12);
    EXPECT_NEAR(f.norm(), 3.3, 1e-12) << "clamped";
    EXPECT_NEAR((model.nodes.mass[17] * a[17]).norm() / (model.nodes.mass[3] * a[3]).norm(), 0.25 / 0.04, 1e-9)
        << "squared weights (R9)";
}

}  // namespace
}  // namespace hapticut::physics
