// Device trajectories: CSV with header `t,x,y,z,button` (s, scene m, buttons: 1 the main one, 2 the
// second, 3 both), optionally `qw,qx,qy,qz` (0,0,0,0 in a sample without an orientation), then `tool`
// (a session: the index of the scene's tool in hand), and recordings of haptic runs, which append
// `fx,fy,fz` (N).
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hapticut/common/result.h"
#include "hapticut/common/text_file.h"
#include "hapticut/haptics/device.h"

namespace hapticut::haptics {

struct TrajectoryPoint {
    double t_s = 0;
    DeviceSample sample;  // position, buttons, orientation (velocity unused)
    int tool = -1;        // a session's: which of the scene's tools the hand held; -1: not recorded
};

struct Trajectory {
    std::vector<TrajectoryPoint> points;  // strictly increasing in time
    double duration_s() const { return points.empty() ? 0 : points.back().t_s - points.front().t_s; }
};

Result<Trajectory, Error> parseTrajectory(std::string_view text, const std::filesystem::path& file_for_errors);
Result<Trajectory, Error> readTrajectory(const std::filesystem::path& file);
std::string formatTrajectory(const Trajectory& trajectory);

}  // namespace hapticut::haptics
