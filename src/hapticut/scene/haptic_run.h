// A haptic run: a device (replayed trajectory) drives the haptic loop on a model; every step is
// logged and the proxy's penetration is measured independently of the proxy.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hapticut/common/stats.h"
#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::scene {

struct HapticRunConfig {
    haptics::LoopConfig loop;
    long steps = -1;          // negative: the trajectory's duration at the loop rate
    bool realtime = false;    // wall-clock rate in the loop's own thread, else as fast as possible
    std::string tool = "probe";
    double toolThreshold_N = 1e9;
};

struct HapticRunResult {
    long steps = 0;
    double simTime_s = 0, wallTime_s = 0;
    double hapticRate_hz = 0;            // steps per wall-clock second
    Summary stepTime_us, periodError_us;
    long overruns = 0, contactSteps = 0, nonFiniteEvents = 0;
    bool watchdogTripped = false;
    double maxForce_N = 0;
    double maxProxyPenetration_m = 0;    // by the ray-parity test on the current surface, every step
    double maxDisplacement_m = 0, finalMaxDisplacement_m = 0;
    int substeps = 1;
    std::vector<haptics::StepOutput> log;  // every step
};

HapticRunResult runHaptic(const mesh::SurfaceMesh& mesh, physics::MassSpringModel& model, const haptics::Trajectory& trajectory,
                          const HapticRunConfig& config);

/// The force log as CSV: t,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,face.
std::string formatForceLog(const std::vector<haptics::StepOutput>& log);

}  // namespace hapticut::scene
