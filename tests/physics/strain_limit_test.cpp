// Provot's strain limit: a stretched spring comes back to the limit about its ends' centre of mass,
// keeps momentum and loses energy; pinned and sleeping ends stay put; on the pressed heart no spring
// stays stretched past it. The reports' largest strain is the formula's over every spring.
#include <gtest/gtest.h>

#include <algorithm>

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"
#include "hapticut/physics/strain_limit.h"
#include "test_support.h"

namespace hapticut::physics {
namespace {

/// Two nodes of 1 kg and 3 kg on a spring of rest length 1 m, 1.5 m apart and parting.
MassSpringModel stretchedPair() {
    MassSpringModel m;
    Nodes& n = m.nodes;
    n.position = {Vec3(0, 0, 0), Vec3(1.5, 0, 0)};
    n.velocity = {Vec3(-1, 0.5, 0), Vec3(2, 0, 0)};
    n.restPosition = n.position;
    n.externalForce.assign(2, Vec3::Zero());
    n.mass = {1, 3};
    n.inverseMass = {1, 1.0 / 3};
    n.anchorStiffness.assign(2, 0.0);
    n.anchorDamping.assign(2, 0.0);
    m.springs.a = {0};
    m.springs.b = {1};
    m.springs.restLength = {1};
    m.springs.stiffness = {10};
    m.springs.damping = {0};
    return m;
}

TEST(StrainLimit, AStretchedSpringComesBackToTheLimitKeepingMomentumAndLosingEnergy) {
    MassSpringModel m = stretchedPair();
    const Vec3 centre = (1 * m.nodes.position[0] + 3 * m.nodes.position[1]) / 4;
    const Vec3 momentum = linearMomentum(m);
    const double energy = kineticEnergy(m);
    const std::uint32_t all[] = {0};
    EXPECT_EQ(limitStrain(m, all, 0.1, {}), 1);
    EXPECT_NEAR((m.nodes.position[1] - m.nodes.position[0]).norm(), 1.1, 1e-12);
    EXPECT_LT(((1 * m.nodes.position[0] + 3 * m.nodes.position[1]) / 4 - centre).norm(), 1e-12);
    EXPECT_LT((linearMomentum(m) - momentum).norm(), 1e-12);
    EXPECT_NEAR((m.nodes.velocity[1] - m.nodes.velocity[0]).x(), 0, 1e-12) << "no longer parting";
    EXPECT_NEAR(m.nodes.velocity[0].y(), 0.5, 1e-12) << "motion across the spring is left alone";
    EXPECT_LT(kineticEnergy(m), energy);
    EXPECT_EQ(limitStrain(m, all, 0.1, {}), 0) << "within the limit: nothing to do";
}

TEST(StrainLimit, APinnedOrSleepingEndStaysWhereItIs) {
    const std::uint32_t all[] = {0};
    MassSpringModel pinned = stretchedPair();
    pinned.nodes.inverseMass[0] = 0;
    limitStrain(pinned, all, 0.1, {});
    EXPECT_EQ(pinned.nodes.position[0], Vec3(0, 0, 0));
    EXPECT_NEAR(pinned.nodes.position[1].x(), 1.1, 1e-12);
    MassSpringModel sleeping = stretchedPair();
    const std::uint8_t awake[] = {1, 0};
    limitStrain(sleeping, all, 0.1, awake);
    EXPECT_EQ(sleeping.nodes.position[1], Vec3(1.5, 0, 0));
    EXPECT_NEAR(sleeping.nodes.position[0].x(), 0.4, 1e-12);
}

/// The largest stretch (not squeeze) of any spring, as a share of its rest length.
double maxStretch(const MassSpringModel& m) {
    double worst = 0;
    for (std::size_t k = 0; k < m.springs.size(); ++k) {
        const double length = (m.nodes.position[m.springs.b[k]] - m.nodes.position[m.springs.a[k]]).norm();
        worst = std::max(worst, length / m.springs.restLength[k] - 1);
    }
    return worst;
}

TEST(StrainLimit, OnTheHeartPressedAtAPointNoSpringStaysStretchedPastIt) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    for (const bool limited : {false, true}) {
        SCOPED_TRACE(limited ? "limited to 10%" : "unlimited");
        MassSpringModel model = buildModel(heart, Material{});
        Stepper stepper(Scheme::RungeKutta4);
        stepper.setActiveRegion(true);
        stepper.setToolStiffness(400);
        if (limited) stepper.setStrainLimit(0.1);
        double worst = 0;
        for (int step = 0; step < 300; ++step) {
            test::pressFrontWithTool(model, heart, step);
            model.tools[0].stiffness_N_per_m = 4000;  // a hard point press, to stretch the springs round it
            model.tools[0].maxForce_N = 20;
            ASSERT_TRUE(stepper.step(model, 1e-3).finite);
            worst = std::max(worst, maxStretch(model));
        }
        if (limited)
            EXPECT_LT(worst, 0.1 + 1e-9);
        else
            EXPECT_GT(worst, 0.2) << "the press stretches springs past the limit when nothing holds them";
    }
}

// The reports' max_strain comes from maxStrain a slice of springs at a time: the largest of
// |length / rest - 1| over the slice, as the formula gives it over every spring, stretched or squeezed.
TEST(StrainLimit, TheLargestStrainIsTheFormulasOverEverySpringOfASlice) {
    MassSpringModel m = buildModel(mesh::procedural::makeHeart({}), Material{});
    for (std::size_t i = 0; i < m.nodes.size(); ++i) m.nodes.position[i] += test::wobble(i, 8e-4);
    const Springs& s = m.springs;
    auto formula = [&](std::size_t first, std::size_t last) {
        double worst = 0;
        for (std::size_t k = first; k < last; ++k)
            worst = std::max(
                worst, std::abs((m.nodes.position[s.b[k]] - m.nodes.position[s.a[k]]).norm() / s.restLength[k] - 1));
        return worst;
    };
    const std::size_t n = s.size();
    for (const auto& [first, last] : {std::pair<std::size_t, std::size_t>{0, n}, {0, 1}, {17, 400}, {n / 2, n}}) {
        const double expected = formula(first, last);
        EXPECT_EQ(maxStrain(m, first, last), expected) << first << "-" << last;
        if (last - first > 100) {
            EXPECT_GT(expected, 0.05);
        }
    }
    // A squeezed spring's strain counts as much as a stretched one's.
    const Vec3 a = m.nodes.position[s.a[5]];
    m.nodes.position[s.b[5]] = a + 0.3 * s.restLength[5] * Vec3::UnitX();
    EXPECT_NEAR(maxStrain(m, 0, n), std::max(0.7, formula(0, n)), 1e-12);
    EXPECT_EQ(maxStrain(m, 0, n), formula(0, n));
}

}  // namespace
}  // namespace hapticut::physics
