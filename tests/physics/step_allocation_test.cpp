// A step of any integrator makes no heap allocation once the stepper is prepared. Its binary links the
// allocation counter, which replaces the global operator new.
#include <gtest/gtest.h>

#include "allocation_counter.h"

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"

namespace hapticut::physics {
namespace {

TEST(Stepper, StepsWithoutHeapAllocation) {
    MassSpringModel model = buildModel(mesh::procedural::makeHeart({}), Material{});
    for (Scheme scheme : {Scheme::ExplicitEuler, Scheme::Midpoint, Scheme::RungeKutta4, Scheme::SymplecticEuler,
                          Scheme::BackwardEuler}) {
        Stepper stepper(scheme);
        stepper.prepare(model);
        model.nodes.externalForce[11] = Vec3(0, 0, -1);
        const long before = test::allocationCount();
        for (int i = 0; i < 1000; ++i) (void)stepper.step(model, 1e-3);
        EXPECT_EQ(test::allocationCount() - before, 0) << schemeName(scheme);
    }
    EXPECT_GT(maxDisplacement(model), 0.0);
}

TEST(Stepper, AnImplicitStepSharedOutOnThreadsAllocatesNothing) {
    mesh::procedural::HeartOptions heart;
    heart.triangles = 9714;  // rows in several chunks, so that the helpers take part
    for (Preconditioner preconditioner : {Preconditioner::BlockJacobi, Preconditioner::Multilevel}) {
        MassSpringModel model = buildModel(mesh::procedural::makeHeart(heart), Material{});
        Stepper stepper(Scheme::BackwardEuler);
        SolverSettings settings;
        settings.threads = 3;
        settings.preconditioner = preconditioner;
        stepper.setSolverSettings(settings);
        stepper.prepare(model);
        model.nodes.externalForce[11] = Vec3(0, 0, -1);
        (void)stepper.step(model, 1e-3);  // the first step makes each thread's scratch space
        const long before = test::allocationCount();
        for (int i = 0; i < 300; ++i) (void)stepper.step(model, 1e-3);
        EXPECT_EQ(test::allocationCount() - before, 0) << preconditionerName(preconditioner);
        EXPECT_GT(maxDisplacement(model), 0.0);
    }
}

// The active region grows as a point load spreads, and every step over a new region lays the multilevel
// preconditioner's levels out afresh: in the room reserved when the stepper was prepared.
TEST(Stepper, TheMultilevelLevelsOfAGrowingRegionAllocateNothing) {
    mesh::procedural::HeartOptions heart;
    heart.triangles = 30'000;
    MassSpringModel model = buildModel(mesh::procedural::makeHeart(heart), Material{});
    Stepper stepper(Scheme::BackwardEuler);
    stepper.setActiveRegion(true);
    stepper.setSolverSettings({.preconditioner = Preconditioner::Multilevel});
    stepper.prepare(model);
    const long before = test::allocationCount();
    std::size_t largest = 0;
    for (int i = 0; i < 200; ++i) {
        model.nodes.externalForce[11] = Vec3(0, 0, -2);
        stepper.wake(11);
        (void)stepper.step(model, 5e-3);
        largest = std::max(largest, stepper.awakeCount());
    }
    EXPECT_EQ(test::allocationCount() - before, 0);
    EXPECT_GT(largest, 200u) << "the region grew past the coarsest level's size";
}

}  // namespace
}  // namespace hapticut::physics
