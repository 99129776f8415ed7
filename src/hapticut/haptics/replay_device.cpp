// A device that replays a recorded trajectory.
#include "hapticut/haptics/replay_device.h"

namespace hapticut::haptics {

DeviceSample ReplayDevice::read(double time_s) {
    const auto& p = trajectory_.points;
    const double t = p.front().t_s + time_s;
    if (t <= p.front().t_s) return p.front().sample;
    if (t >= p.back().t_s) return p.back().sample;
    if (p[cursor_].t_s > t) cursor_ = 0;  // time went backwards (a reset): search from the start
    while (cursor_ + 1 < p.size() && p[cursor_ + 1].t_s < t) ++cursor_;
    const TrajectoryPoint &a = p[cursor_], &b = p[cursor_ + 1];
    const double u = (t - a.t_s) / (b.t_s - a.t_s);
    DeviceSample s;
    s.position_m = (1 - u) * a.sample.position_m + u * b.sample.position_m;
    s.velocity_m_per_s = (b.sample.position_m - a.sample.position_m) / (b.t_s - a.t_s);
    s.orientation = a.sample.orientation.slerp(u, b.sample.orientation);
    s.oriented = a.sample.oriented;
    s.buttons = u < 0.5 ? a.sample.buttons : b.sample.buttons;
    return s;
}

}  // namespace hapticut::haptics
