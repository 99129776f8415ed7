// The haptic device interface: position in, force out, in scene units (metres, newtons).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "hapticut/common/error.h"
#include "hapticut/geometry/aabb.h"
#include "hapticut/geometry/vec.h"

namespace hapticut::haptics {

struct DeviceSample {
    Vec3 position_m = Vec3::Zero();
    Vec3 velocity_m_per_s = Vec3::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    /// Whether the device reports its stylus's orientation (a Phantom, a trajectory with quaternions, the
    /// mouse once its blade is turned); without it a blade cuts the way it moves.
    bool oriented = false;
    std::uint32_t buttons = 0;  // bit 0: the main stylus button
};

/// Device units to scene metres: scene = rotation * (scale * device) + offset.
struct WorkspaceTransform {
    double scale = 1;
    Vec3 offset_m = Vec3::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();

    Vec3 toScene(const Vec3& device) const { return rotation * (scale * device) + offset_m; }
    Vec3 velocityToScene(const Vec3& device_velocity) const { return rotation * (scale * device_velocity); }
    /// Forces are not scaled: a newton in the scene is a newton in the hand.
    Vec3 forceToDevice(const Vec3& scene_force_N) const { return rotation.conjugate() * scene_force_N; }
};

/// A device whose driver owns the servo loop (OpenHaptics' scheduler): the driver calls `tick` at its
/// own rate on its own thread, and the haptic loop steps inside it instead of running a thread of its own.
class ServoClock {
public:
    virtual ~ServoClock() = default;
    /// Starts calling `tick` at the servo rate until it returns false or stopServo(); an error when the
    /// servo cannot start.
    virtual Status startServo(std::function<bool()> tick) = 0;
    /// Stops calling `tick` and returns once the last call has finished. Safe to call twice.
    virtual void stopServo() = 0;
    virtual double servoRate_hz() const = 0;
};

class Device {
public:
    virtual ~Device() = default;
    virtual std::string_view name() const = 0;
    /// The device state at simulated time t, already in scene metres. Called from the haptic thread only.
    virtual DeviceSample read(double time_s) = 0;
    /// The force to render, in the scene frame. Called from the haptic thread only.
    virtual void commandForce(const Vec3& force_N) = 0;
    virtual double maxForce_N() const = 0;
    /// The stiffest coupling the device renders stably at a 1 kHz servo rate (OpenHaptics' nominal
    /// maximum stiffness); infinite for devices without such a limit.
    virtual double maxStiffness_N_per_m() const { return std::numeric_limits<double>::infinity(); }
    /// How device units map to the scene (identity for devices that already speak scene metres).
    virtual WorkspaceTransform workspace() const { return {}; }
    /// The box the device reaches, in device units, for devices that map a workspace of their own.
    virtual std::optional<geometry::Aabb> workspaceBox() const { return std::nullopt; }
    /// Changes the mapping; false for devices without one. Before the loop starts only.
    virtual bool setWorkspace(const WorkspaceTransform&) { return false; }
    /// The device's own servo loop, if it has one (see ServoClock).
    virtual ServoClock* servoClock() { return nullptr; }
};

/// Force a Phantom Omni / Touch can exert continuously-ish; the default clamp.
inline constexpr double kDefaultMaxForce_N = 3.3;

}  // namespace hapticut::haptics
