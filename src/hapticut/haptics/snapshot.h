// What the haptic loop hands the renderer and the panel: the deformed organ, each hand's tool, the loop's health.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "hapticut/cutting/progressive_cutter.h"
#include "hapticut/mesh/surface_mesh.h"
#include "hapticut/physics/point_spring.h"
#include "hapticut/physics/scheme.h"

namespace hapticut::haptics {

inline constexpr int kMaxHands = physics::kMaxTools;

/// What one hand did in one step.
struct HandStep {
    Vec3 device_m = Vec3::Zero(), proxy_m = Vec3::Zero(), force_N = Vec3::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // the stylus's, when `oriented`
    bool oriented = false;
    bool contact = false;
    bool cutting = false;  // its blade presses into uncut tissue at the end of its cut: it feels the resistance
    std::uint32_t face = 0;
    std::uint32_t buttons = 0;
    /// Which of the scene's tools the hand holds, when its owner says (scene::Simulation, for a session's
    /// recording); the loop knows thresholds and tips, not tools, and leaves -1.
    int tool = -1;
};

/// What the renderer reads: the deformed positions, the faces when a cut changed them, and the tool state.
struct Snapshot {
    std::vector<Vec3> positions;
    std::vector<mesh::Face> faces;  // brought up to date only when topologyVersion changes
    std::vector<mesh::FaceUvs> uvs;
    std::vector<std::uint8_t> wallFaces;  // per face: 1 for a wound's wall (CutModel::wallFaces)
    long topologyVersion = -1;
    std::array<HandStep, kMaxHands> hands{};
    int handCount = 1;
    long step = 0;
    // The loop's health, for the viewer's panel: reading LoopStats from another thread would race.
    double stepTime_us = 0;     // of the step that published this
    double maxStepTime_us = 0;  // the slowest step since the previous snapshot
    double stableStep_s = 0;    // the integrator's stable step on the current model
    int substeps = 1;
    physics::Scheme scheme = physics::Scheme::RungeKutta4;  // the one in use (Auto resolved)
    int solverIterations = 0;                               // the implicit scheme's, in the latest step
    bool solverMultilevel = false;                          // ... preconditioned by the multilevel cycle
    bool multiRate = false;
    double physicsRate_hz = 0;         // physics steps per second: the loop's rate unless multi-rate
    double physicsRealtimeFactor = 1;  // simulated physics time per second of the loop's
    double physicsStep_s = 0;          // how long the latest physics step took to compute
    long overruns = 0, stalls = 0, cutEvents = 0, contactSteps = 0;
    cutting::CutStats cut{};  // the cutter's counts since the loop started: cuts, their length, wounds crossed
    bool watchdogTripped = false, paused = false;
};

}  // namespace hapticut::haptics
