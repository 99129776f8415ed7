// A joystick, gamepad or wheel through SDL2 as a haptic device: its axes move the tool (position or
// rate control), SDL's constant-force effect pushes back where the device has one, rumble says
// "touching" where it has only that. SDL runs on a thread of the device's own, so the haptic loop only
// exchanges lock-free state with it.
#pragma once

#include <array>
#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/common/triple_buffer.h"
#include "hapticut/haptics/device.h"

namespace hapticut::haptics {

enum class SdlControl {
    Position,  // the stick's deflection is the position in the workspace box
    Rate,      // the deflection is a velocity: the tool keeps moving while the stick is held
};

struct SdlOptions {
    int index = 0;  // SDL's joystick index (hapticut devices lists them)
    SdlControl control = SdlControl::Position;
    /// Which axis drives device x (right), y (up) and z (toward the user); -1: none. A gamepad's left
    /// stick moves across the organ and in/out of it, the right stick's vertical moves up and down.
    std::array<int, 3> axes{0, 4, 1};
    std::array<bool, 3> invert{false, true, false};  // SDL's axes grow downward and away
    double deadZone = 0.08;                          // fraction of full deflection ignored round the centre
    double rate_per_s = 1.0;  // rate control: workspace half-widths per second at full deflection
    /// Device units (-1..1 on every axis) to scene metres; the automatic fit replaces it.
    WorkspaceTransform workspace{0.05};
    double maxForce_N = kDefaultMaxForce_N;  // the scene force that plays as the effect's full strength
    double pollRate_hz = 1000;               // how often the device's thread reads the axes
    double effectRate_hz = 100;              // how often it renews the force effect (USB devices are slow)
};

/// What SDL sees, for `hapticut devices`.
struct SdlJoystickInfo {
    int index = 0;
    std::string name;
    int axes = 0, buttons = 0;
    bool constantForce = false;  // a force-feedback effect we can steer
    bool rumble = false;
};

class SdlDevice final : public Device {
public:
    /// Opens joystick `options.index` on a thread of its own; an error saying what SDL saw (no
    /// joystick, which indices exist) and what to check.
    static Result<std::unique_ptr<SdlDevice>, Error> open(const SdlOptions& options);
    /// Every joystick SDL sees now; an error when SDL's joystick support does not start.
    static Result<std::vector<SdlJoystickInfo>, Error> list();
    ~SdlDevice() override;

    std::string_view name() const override { return "sdl"; }
    DeviceSample read(double time_s) override;
    void commandForce(const Vec3& force_N) override;
    double maxForce_N() const override { return options_.maxForce_N; }
    WorkspaceTransform workspace() const override { return options_.workspace; }
    std::optional<geometry::Aabb> workspaceBox() const override {
        return geometry::Aabb{Vec3::Constant(-1), Vec3::Constant(1)};
    }
    bool setWorkspace(const WorkspaceTransform& workspace) override {
        options_.workspace = workspace;
        return true;
    }

    const SdlJoystickInfo& info() const { return info_; }
    /// How the force reaches the hand: "constant force", "rumble" or "none".
    std::string_view feedback() const;
    /// Samples the device's thread has published (it is alive and reading).
    long polls() const { return polls_.load(std::memory_order_relaxed); }
    /// The strength (0..1) the device's thread last played, for tests and the self-test.
    double playedStrength() const { return played_.load(std::memory_order_relaxed); }
    /// Set when the joystick was unplugged: from then on it reads as non-finite, which trips the
    /// loop's watchdog.
    bool lost() const { return lost_.load(std::memory_order_acquire); }

private:
    struct Sdl;
    SdlDevice() = default;
    void threadMain(std::string* error, std::atomic<int>* started);

    SdlOptions options_;
    SdlJoystickInfo info_;
    std::unique_ptr<Sdl> sdl_;
    std::thread thread_;
    std::atomic<bool> stop_{false}, lost_{false};
    std::atomic<long> polls_{0};
    std::atomic<double> fx_{0}, fy_{0}, fz_{0}, played_{0};
    struct Input {
        Vec3 position = Vec3::Zero();  // device units
        Vec3 velocity = Vec3::Zero();  // device units per second
        std::uint32_t buttons = 0;
    };
    TripleBuffer<Input> input_;
};

}  // namespace hapticut::haptics
