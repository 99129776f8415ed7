// A step of any integrator makes no heap allocation once the stepper is prepared. This binary replaces
// the global operator new to count allocations, so it holds only this test.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"

namespace {
std::atomic<long> gAllocations{0};
}

void* operator new(std::size_t size) {
    ++gAllocations;
    if (void* p = std::malloc(size ? size : 1)) return p;
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace hapticut::physics {
namespace {

TEST(Stepper, StepsWithoutHeapAllocation) {
    MassSpringModel model = buildModel(mesh::procedural::makeHeart({}), Material{});
    for (Scheme scheme : {Scheme::ExplicitEuler, Scheme::Midpoint, Scheme::RungeKutta4, Scheme::SymplecticEuler}) {
        Stepper stepper(scheme);
        stepper.prepare(model);
        model.nodes.externalForce[11] = Vec3(0, 0, -1);
        const long before = gAllocations.load();
        for (int i = 0; i < 1000; ++i) (void)stepper.step(model, 1e-3);
        EXPECT_EQ(gAllocations.load() - before, 0) << schemeName(scheme);
    }
    EXPECT_GT(maxDisplacement(model), 0.0);
}

}  // namespace
}  // namespace hapticut::physics
