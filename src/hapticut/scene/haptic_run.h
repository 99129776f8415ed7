// A haptic run: devices, one per hand (a replayed trajectory, or live ones in real time), drive the haptic loop on an
// organ; every step is logged and the proxy's penetration is measured independently of the proxy.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/latency_histogram.h"
#include "hapticut/common/result.h"
#include "hapticut/common/stats.h"
#include "hapticut/cutting/cut_model.h"
#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/step_log.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::scene {

struct HapticRunConfig {
    haptics::LoopConfig loop;
    long steps = -1;             // negative: the trajectory's duration at the loop rate
    bool realtime = false;       // wall-clock rate in the loop's own thread, else as fast as possible
    std::string tool = "probe";  // its cut threshold is config.loop.cutThreshold_N
    /// Polled every few milliseconds (real time) or every few steps (simulated time); true ends the
    /// run (Ctrl-C). With steps < 0 a real-time run goes on until it says so.
    std::function<bool()> stopRequested;
    /// Seconds since the stop was asked for (the signal's own time), read once the loop has stopped:
    /// the run's stop latency. Unset: timed from when the run noticed the request.
    std::function<double()> stopRequestedAgo_s;
    /// Called about once a second with the steps done so far.
    std::function<void(long)> progress;
    /// Every step goes here as it happens (the force log, the recording), if set: a run of any length
    /// keeps nothing per step in memory.
    haptics::StepLogWriter* stepLog = nullptr;
    /// Called after every step on the stepping thread, with the loop, for what watches a run closely
    /// (an exercise's assessment reads the cutter and switches tools through the loop's commands).
    /// Simulated time only: a real-time run refuses it.
    std::function<void(const haptics::StepOutput&, haptics::HapticLoop&)> afterStep;
    /// The first this many steps are also kept in HapticRunResult::keptSteps (tests, short runs).
    long keepSteps = 0;
};

/// What one hand did over the run.
struct HandSummary {
    double maxForce_N = 0;
    long contactSteps = 0;
};

struct HapticRunResult {
    long steps = 0;
    double simTime_s = 0, wallTime_s = 0;
    double hapticRate_hz = 0;  // steps per wall-clock second
    Summary stepTime_us, periodError_us;
    long overruns = 0, contactSteps = 0, nonFiniteEvents = 0;
    long contactNodesMax = 0, footprintCutSteps = 0;  // LoopStats': how far the tools' loads spread
    long missedPeriods = 0, stalls = 0;               // LoopStats'
    std::string hapticScheduling;  // on the wall clock, how the stepping thread ran (RealTimeScheduler::scheduling)
    bool watchdogTripped = false;
    double maxForce_N = 0;
    double maxProxyPenetration_m = 0;   // by the ray-parity test on the current surface, in every step it is closed
    long penetrationMeasuredSteps = 0;  // the steps in which it was (all, on a closed organ whose wounds have walls)
    // How often a proxy was found inside and pushed out to the surface (GodObjectProxy::pushOuts), and
    // the deepest it was then: what the penetration above, measured after each update, cannot see.
    long proxyPushOuts = 0;
    double proxyDeepestPushOut_m = 0;
    double maxDisplacement_m = 0, finalMaxDisplacement_m = 0;
    // In passes over the organ, a slice a step: the enclosed volume's change from what the anchors
    // enclose (closed organs whose wounds have walls) and the largest spring strain.
    double volumeChangeMax_pct = 0, maxStrain = 0;
    long volumeMeasurements = 0;
    bool volumeKept = false;  // the loop kept the volume by a pressure (LoopConfig::bulkModulus_Pa)
    physics::Scheme scheme = physics::Scheme::RungeKutta4;  // the one used (Auto resolved)
    int substeps = 1;
    physics::SolverStats solver;       // the implicit scheme's solves
    bool multiRate = false;            // the physics ran on its own thread (or every few steps in simulated time)
    double multiRateFrom_s = -1;       // from this loop time on (0: from the start); -1: never
    long multiRateSwitchSteps = 0;     // Auto's switch: haptic steps taken while the physics' copy was made
    double physicsRate_hz = 0;         // physics steps per wall-clock second
    double physicsRealtimeFactor = 0;  // simulated physics seconds per wall-clock second
    double maxPhysicsStep_s = 0;       // multi-rate: the longest a physics step may simulate (LoopConfig)
    Summary physicsStepTime_us;        // how long the physics' steps took to compute
    double physicsTimeLost_s = 0;      // multi-rate: wall time left unsimulated, over 2 maxPhysicsStep_s behind
    double physicsLagAtEnd_s = 0;      // multi-rate: the wall time not yet simulated when the run ended
    // Cutting: what the scalpel did, how long cut events took, and whether the organ stayed sound.
    cutting::CutStats cut;
    long cutEvents = 0;
    Summary cutTime_us;
    // The force on the blade while it was in a cut it was making (HandStep::cutting), N.
    long cuttingSteps = 0;
    Summary cuttingForce_N;
    double minCuttingForce_N = 0;
    Summary syncTime_us;  // multi-rate: cuts and edits copied into the physics' copy, a step after each
    /// Broken invariants at the end that were not broken before the run: what the run (its cuts) broke.
    std::vector<std::string> invariantProblems;
    /// Broken before the run began: the model's own defects (an unrepaired import), never a cut's.
    std::vector<std::string> defectsAtLoad;
    /// Each named part of the model (empty for one part): a piece of its own, pressed and cut as such.
    struct Part {
        std::string name;
        std::size_t facesAtStart = 0, faces = 0, boundaryEdges = 0;
        double maxDisplacement_m = 0;  // of its nodes from rest, at the end
    };
    std::vector<Part> parts;
    std::array<HandSummary, haptics::kMaxHands> hands{};
    int handCount = 1;
    std::vector<haptics::StepOutput> keptSteps;  // the first HapticRunConfig::keepSteps steps
    haptics::StepOutput lastStep;                // the run's last step
    long droppedLogSteps = 0;                    // steps the step log's ring had no room for (real time)
    bool stoppedEarly = false;                   // stopRequested ended a run before its step count
    double stopLatency_s = -1;                   // from the request to the loop stopped, forces zeroed; -1: none
};

/// Replays the trajectory through the haptic loop on the organ, which the tool cuts when
/// config.loop.cutThreshold_N is below the force it presses with.
Result<HapticRunResult, Error> runHaptic(cutting::CutModel& organ, const haptics::Trajectory& trajectory,
                                         const HapticRunConfig& config);
/// Any devices, one per hand, each with its tool's threshold. config.steps must be given unless the
/// run is real time and config.stopRequested ends it. An error when the loop cannot be built or a
/// device's servo cannot start.
Result<HapticRunResult, Error> runHaptic(cutting::CutModel& organ, std::span<const haptics::Hand> hands,
                                         const HapticRunConfig& config);

}  // namespace hapticut::scene
