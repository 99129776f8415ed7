// A device that replays a recorded trajectory, linearly interpolated in time.
#pragma once

#include "hapticut/haptics/device.h"
#include "hapticut/haptics/trajectory.h"

namespace hapticut::haptics {

class ReplayDevice final : public Device {
public:
    explicit ReplayDevice(Trajectory trajectory, double max_force_N = kDefaultMaxForce_N)
        : trajectory_(std::move(trajectory)), maxForce_(max_force_N) {}

    std::string_view name() const override { return "replay"; }
    /// Before the first sample it holds the first, after the last it holds the last. Time is measured
    /// from the first sample's time.
    DeviceSample read(double time_s) override;
    void commandForce(const Vec3& force_N) override { lastForce_ = force_N; }
    double maxForce_N() const override { return maxForce_; }

    const Trajectory& trajectory() const { return trajectory_; }
    const Vec3& lastForce() const { return lastForce_; }

private:
    Trajectory trajectory_;
    double maxForce_;
    std::size_t cursor_ = 0;  // the segment last used: reads move forward, so lookups are O(1) on average
    Vec3 lastForce_ = Vec3::Zero();
};

}  // namespace hapticut::haptics
