// The haptic loop makes no heap allocation in steady state. Its binary links the
// allocation counter, which replaces the global operator new.
#include <gtest/gtest.h>

#include "allocation_counter.h"

#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"

namespace hapticut::haptics {
namespace {

class SteadyState : public ::testing::TestWithParam<LoopConfig::PhysicsRate> {};

// Single-rate, and multi-rate with its physics stepped in simulated time: frames, tools, refits.
TEST_P(SteadyState, StepsWithoutHeapAllocation) {
    const mesh::SurfaceMesh mesh = mesh::procedural::makeHeart({});
    cutting::CutModel organ(mesh, physics::buildModel(mesh, physics::Material{}));
    VirtualDevice device;
    LoopConfig config;
    config.physicsRate = GetParam();
    config.tipRadius_m = mesh::procedural::kProbeTipRadius_m;  // the tools' footprints, as users get them
    HapticLoop loop(organ, device, config);
    ASSERT_EQ(loop.multiRate(), GetParam() == LoopConfig::PhysicsRate::Multi);
    // Sweep the device in and out of the front of the heart: contact, sliding, release.
    auto at = [](int i) { return Vec3(0.01 * std::sin(i * 0.01), 0.0, 0.03 - 0.0004 * (i % 100)); };
    for (int i = 0; i < 200; ++i) {
        device.setPosition(at(i));
        loop.step();
    }
    const long before = test::allocationCount();
    for (int i = 200; i < 3200; ++i) {
        device.setPosition(at(i));
        loop.step();
        if (i % 50 == 0) loop.commands().push({LoopCommand::Kind::SetCouplingStiffness, 400.0 + i % 7});
        if (i % 500 == 0) loop.commands().push({LoopCommand::Kind::SetTipRadius, i % 1000 ? 0.004 : 0.007});
    }
    EXPECT_EQ(test::allocationCount() - before, 0);
    EXPECT_GT(loop.stats().contactSteps, 500);
    EXPECT_GT(loop.stats().physicsSteps, 700);
}

INSTANTIATE_TEST_SUITE_P(HapticLoop, SteadyState,
                         ::testing::Values(LoopConfig::PhysicsRate::Single, LoopConfig::PhysicsRate::Multi));

}  // namespace
}  // namespace hapticut::haptics
