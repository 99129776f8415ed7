// The SDL2 backend against SDL's own virtual joystick (no hardware, no display): axes move the device
// through the workspace mapping in position and rate control, the force plays as rumble in proportion,
// unplugging trips the watchdog's non-finite path, and a missing joystick is named with what exists.
#include <gtest/gtest.h>

#include <SDL.h>

#include <chrono>
#include <thread>

#include "hapticut/haptics/sdl_device.h"
#include "test_support.h"

namespace hapticut::haptics {
namespace {

using namespace std::chrono_literals;

/// The device, or nothing with `error` holding the message.
std::unique_ptr<SdlDevice> openOrSay(const SdlOptions& options, std::string& error) {
    return test::valueOrMessage(SdlDevice::open(options), error);
}

/// A gamepad SDL believes in, whose rumble the test can hear.
class VirtualPad : public ::testing::Test {
protected:
    void SetUp() override {
        SDL_SetHint(SDL_HINT_JOYSTICK_HIDAPI, "0");  // only the virtual pad: no scanning of real devices
        ASSERT_EQ(SDL_InitSubSystem(SDL_INIT_JOYSTICK), 0) << SDL_GetError();
        SDL_VirtualJoystickDesc desc{};
        desc.version = SDL_VIRTUAL_JOYSTICK_DESC_VERSION;
        desc.type = SDL_JOYSTICK_TYPE_GAMECONTROLLER;
        desc.naxes = 6;
        desc.nbuttons = 4;
        desc.name = "Hapticut test pad";
        desc.userdata = this;
        desc.Rumble = [](void* self, Uint16 low, Uint16 high) {
            static_cast<VirtualPad*>(self)->rumble.store(std::max(low, high));
            return 0;
        };
        index = SDL_JoystickAttachVirtualEx(&desc);
        ASSERT_GE(index, 0) << SDL_GetError();
        pad = SDL_JoystickOpen(index);
        ASSERT_NE(pad, nullptr) << SDL_GetError();
    }
    void TearDown() override {
        if (pad && SDL_JoystickGetAttached(pad)) SDL_JoystickClose(pad);
        if (index >= 0) SDL_JoystickDetachVirtual(index);
        SDL_QuitSubSystem(SDL_INIT_JOYSTICK);
    }
    void setAxis(int axis, double value) { SDL_JoystickSetVirtualAxis(pad, axis, static_cast<Sint16>(value * 32767)); }
    /// Waits until the device's thread has read the pad a few more times.
    static void settle(const SdlDevice& d) {
        const long from = d.polls();
        for (int i = 0; i < 500 && d.polls() < from + 5; ++i) std::this_thread::sleep_for(1ms);
    }

    int index = -1;
    SDL_Joystick* pad = nullptr;
    std::atomic<Uint16> rumble{0};
};

TEST_F(VirtualPad, TheSticksMoveTheDeviceThroughItsWorkspaceMapping) {
    SdlOptions options;
    options.index = index;
    options.workspace.scale = 0.05;
    options.workspace.offset_m = Vec3(0, 0, 0.1);
    std::string error;
    auto device = openOrSay(options, error);
    ASSERT_TRUE(device) << error;
    EXPECT_EQ(device->info().name, "Hapticut test pad");
    EXPECT_EQ(device->info().axes, 6);
    setAxis(0, 1.0);   // right
    setAxis(1, -1.0);  // pushed away: into the scene
    setAxis(4, -0.5);  // right stick up: up
    settle(*device);
    const DeviceSample s = device->read(0);
    EXPECT_NEAR(s.position_m.x(), 0.05, 1e-3);
    EXPECT_NEAR(s.position_m.z(), 0.1 - 0.05, 1e-3) << "forward on the stick is into the scene";
    EXPECT_NEAR(s.position_m.y(), 0.05 * (0.5 - 0.08) / 0.92, 1e-3) << "past the dead zone, rescaled";
    setAxis(0, 0.05);  // inside the dead zone
    settle(*device);
    EXPECT_NEAR(device->read(0).position_m.x(), 0, 1e-12);
    SDL_JoystickSetVirtualButton(pad, 0, 1);
    settle(*device);
    EXPECT_EQ(device->read(0).buttons & 1u, 1u);
}

TEST_F(VirtualPad, RateControlKeepsMovingWhileTheStickIsHeldAndStopsAtTheEdge) {
    SdlOptions options;
    options.index = index;
    options.control = SdlControl::Rate;
    options.rate_per_s = 2.0;  // half the box a quarter-second
    std::string error;
    auto device = openOrSay(options, error);
    ASSERT_TRUE(device) << error;
    setAxis(0, 1.0);
    std::this_thread::sleep_for(200ms);
    const double moving = device->read(0).position_m.x();
    EXPECT_GT(moving, 0.05 * 0.1) << "it moved";
    std::this_thread::sleep_for(1200ms);
    EXPECT_NEAR(device->read(0).position_m.x(), 0.05, 1e-9) << "held at the workspace's edge";
    setAxis(0, 0.0);
    settle(*device);
    const double held = device->read(0).position_m.x();
    std::this_thread::sleep_for(50ms);
    EXPECT_DOUBLE_EQ(device->read(0).position_m.x(), held) << "let go, it stays";
}

TEST_F(VirtualPad, AForceWithoutAForceFeedbackEffectPlaysAsRumbleInProportion) {
    SdlOptions options;
    options.index = index;
    options.maxForce_N = 4;
    options.effectRate_hz = 200;
    std::string error;
    auto device = openOrSay(options, error);
    ASSERT_TRUE(device) << error;
    EXPECT_EQ(device->feedback(), "rumble");
    device->commandForce(Vec3(0, 0, 2));
    for (int i = 0; i < 500 && rumble.load() == 0; ++i) std::this_thread::sleep_for(1ms);
    EXPECT_NEAR(rumble.load() / 65535.0, 0.5, 0.01);
    EXPECT_NEAR(device->playedStrength(), 0.5, 1e-9);
    device->commandForce(Vec3(0, 0, 40));
    std::this_thread::sleep_for(30ms);
    EXPECT_EQ(rumble.load(), 65535) << "clamped at full strength";
    device.reset();
    EXPECT_EQ(rumble.load(), 0) << "closing the device stops it";
}

TEST_F(VirtualPad, AnUnpluggedPadReadsAsNonFinite) {
    SdlOptions options;
    options.index = index;
    std::string error;
    auto device = openOrSay(options, error);
    ASSERT_TRUE(device) << error;
    settle(*device);
    EXPECT_TRUE(device->read(0).position_m.allFinite());
    SDL_JoystickClose(pad);
    pad = nullptr;
    ASSERT_EQ(SDL_JoystickDetachVirtual(index), 0) << SDL_GetError();
    index = -1;
    for (int i = 0; i < 500 && !device->lost(); ++i) std::this_thread::sleep_for(1ms);
    EXPECT_TRUE(device->lost());
    EXPECT_FALSE(device->read(0).position_m.allFinite()) << "which trips the loop's watchdog";
}

TEST_F(VirtualPad, AMissingJoystickIsNamedWithTheOnesThatExist) {
    SdlOptions options;
    options.index = index + 5;
    std::string error;
    EXPECT_FALSE(openOrSay(options, error));
    EXPECT_NE(error.find("no joystick " + std::to_string(index + 5)), std::string::npos) << error;
    EXPECT_NE(error.find("Hapticut test pad"), std::string::npos) << error;
    const auto listed = SdlDevice::list();
    ASSERT_TRUE(listed.has_value()) << listed.error().message;
    const std::vector<SdlJoystickInfo>& all = *listed;
    ASSERT_FALSE(all.empty());
    EXPECT_EQ(all.back().name, "Hapticut test pad");
    EXPECT_TRUE(all.back().rumble);
    EXPECT_FALSE(all.back().constantForce);
}

}  // namespace
}  // namespace hapticut::haptics
