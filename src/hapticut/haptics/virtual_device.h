// A device set programmatically (tests, scripts, the viewer's mouse): lock-free between threads.
#pragma once

#include <atomic>
#include <optional>
#include <string>

#include "hapticut/common/triple_buffer.h"
#include "hapticut/haptics/device.h"

namespace hapticut::haptics {

class VirtualDevice final : public Device {
public:
    explicit VirtualDevice(double max_force_N = kDefaultMaxForce_N, WorkspaceTransform workspace = {})
        : maxForce_(max_force_N), workspace_(workspace) {}

    /// From any one thread (the UI): where the device is now, in device units.
    void setPosition(const Vec3& position, std::uint32_t buttons = 0);
    /// The same with the device's velocity given (a script that knows its path), used instead of the
    /// finite difference over the haptic step; device units per second.
    void setMotion(const Vec3& position, const Vec3& velocity, std::uint32_t buttons = 0);
    /// From the same thread: the stylus's orientation from now on (the viewer turns the mouse's blade).
    void setOrientation(const Eigen::Quaterniond& orientation);
    /// The last force commanded, for display; safe from any thread.
    Vec3 lastForce() const;
    /// Follow new positions with a first-order lag of this time constant (0, the default: jump to them).
    /// For inputs that update far slower than the loop, such as a mouse at the display's frame rate.
    /// Set before the loop starts.
    void setFollowTime(double seconds) { followTime_s_ = seconds; }

    std::string_view name() const override { return "virtual"; }
    DeviceSample read(double time_s) override;
    void commandForce(const Vec3& force_N) override;
    double maxForce_N() const override { return maxForce_; }
    WorkspaceTransform workspace() const override { return workspace_; }

private:
    struct Input {
        Vec3 position = Vec3::Zero();
        std::optional<Vec3> velocity;  // given with the position; else a finite difference
        std::uint32_t buttons = 0;
        Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
        bool oriented = false;
    };
    double maxForce_;
    WorkspaceTransform workspace_;
    TripleBuffer<Input> input_;
    Input latest_;  // what the writing thread last set
    std::atomic<double> fx_{0}, fy_{0}, fz_{0};
    Vec3 lastPosition_ = Vec3::Zero();
    double lastTime_ = -1;
    double followTime_s_ = 0;
};

}  // namespace hapticut::haptics
