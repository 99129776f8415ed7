// A device set programmatically.
#include "hapticut/haptics/virtual_device.h"

#include <algorithm>

namespace hapticut::haptics {

void VirtualDevice::setPosition(const Vec3& position, std::uint32_t buttons) {
    latest_.position = position;
    latest_.velocity.reset();
    latest_.buttons = buttons;
    input_.writeSlot() = latest_;
    input_.publish();
}

void VirtualDevice::setMotion(const Vec3& position, const Vec3& velocity, std::uint32_t buttons) {
    latest_.position = position;
    latest_.velocity = velocity;
    latest_.buttons = buttons;
    input_.writeSlot() = latest_;
    input_.publish();
}

void VirtualDevice::setOrientation(const Eigen::Quaterniond& orientation) {
    latest_.orientation = orientation.normalized();
    latest_.oriented = true;
    input_.writeSlot() = latest_;
    input_.publish();
}

Vec3 VirtualDevice::lastForce() const {
    return {fx_.load(std::memory_order_relaxed), fy_.load(std::memory_order_relaxed),
            fz_.load(std::memory_order_relaxed)};
}

DeviceSample VirtualDevice::read(double time_s) {
    const Input& in = input_.readLatest();
    DeviceSample s;
    s.position_m = workspace_.toScene(in.position);
    // A hand moves smoothly; a cursor jumps once a frame. Following it with a first-order lag spreads
    // each jump over the haptic steps, so the coupling's damping sees a hand's speed, not a spike.
    if (followTime_s_ > 0 && lastTime_ >= 0 && time_s > lastTime_)
        s.position_m =
            lastPosition_ + (s.position_m - lastPosition_) * std::min(1.0, (time_s - lastTime_) / followTime_s_);
    s.buttons = in.buttons;
    s.orientation = workspace_.rotation * in.orientation;
    s.oriented = in.oriented;
    // Velocity as given, or by finite difference over the haptic step; the first sample has none.
    if (in.velocity)
        s.velocity_m_per_s = workspace_.velocityToScene(*in.velocity);
    else if (lastTime_ >= 0 && time_s > lastTime_)
        s.velocity_m_per_s = (s.position_m - lastPosition_) / (time_s - lastTime_);
    lastPosition_ = s.position_m;
    lastTime_ = time_s;
    return s;
}

void VirtualDevice::commandForce(const Vec3& force_N) {
    fx_.store(force_N.x(), std::memory_order_relaxed);
    fy_.store(force_N.y(), std::memory_order_relaxed);
    fz_.store(force_N.z(), std::memory_order_relaxed);
}

}  // namespace hapticut::haptics
