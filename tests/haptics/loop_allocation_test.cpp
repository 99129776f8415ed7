// The haptic loop makes no heap allocation in steady state. This binary replaces the global operator
// new to count allocations, so it holds only this test.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/mesh/procedural/heart.h"
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

namespace hapticut::haptics {
namespace {

TEST(HapticLoop, SteadyStateStepsWithoutHeapAllocation) {
    const mesh::SurfaceMesh mesh = mesh::procedural::makeHeart({});
    physics::MassSpringModel model = physics::buildModel(mesh, physics::Material{});
    VirtualDevice device;
    HapticLoop loop(model, mesh.faces, device);
    // Sweep the device in and out of the front of the heart: contact, sliding, release.
    auto at = [](int i) { return Vec3(0.01 * std::sin(i * 0.01), 0.0, 0.03 - 0.0004 * (i % 100)); };
    for (int i = 0; i < 200; ++i) {
        device.setPosition(at(i));
        loop.step();
    }
    const long before = gAllocations.load();
    for (int i = 200; i < 3200; ++i) {
        device.setPosition(at(i));
        loop.step();
        if (i % 50 == 0) loop.commands().push({LoopCommand::Kind::SetCouplingStiffness, 400.0 + i % 7});
    }
    EXPECT_EQ(gAllocations.load() - before, 0);
    EXPECT_GT(loop.stats().contactSteps, 500);
}

}  // namespace
}  // namespace hapticut::haptics
