// The haptic loop (DESIGN "The loop"): device -> proxy -> force -> tissue -> physics -> device, at
// 1 kHz by default, in simulated time or in its own real-time thread.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "hapticut/collision/bvh.h"
#include "hapticut/common/latency_histogram.h"
#include "hapticut/common/spsc_queue.h"
#include "hapticut/common/triple_buffer.h"
#include "hapticut/cutting/progressive_cutter.h"
#include "hapticut/haptics/device.h"
#include "hapticut/haptics/proxy.h"
#include "hapticut/physics/integrators.h"

namespace hapticut::haptics {

struct LoopConfig {
    double rate_hz = 1000;                     // 1 kHz (R7); up to 10 kHz
    physics::Scheme scheme = physics::Scheme::RungeKutta4;
    double couplingStiffness_N_per_m = 400;    // k_h of the virtual spring between proxy and device; live changes up to this value.
                                               // 400 N/m keeps RK4 at one step per ms on the 1,619 heart.
    double couplingDamping_Ns_per_m = 0.3;     // b_h on the device velocity, only while in contact
    double rampTime_s = 0.5;                   // force fades in over this long after start
    int snapshotEvery = 8;                     // publish positions for the renderer every N steps (125 Hz)
    bool activeRegion = true;                  // integrate only the tissue near the tool (Stepper::setActiveRegion)
    /// The tool cuts while its force is above this (R14): the scalpel's threshold; the probe's is infinite.
    /// Only a loop built on a CutModel cuts.
    double cutThreshold_N = std::numeric_limits<double>::infinity();
    ProxyParams proxy;
    cutting::CutterParams cutter;
};

/// What one step did, for logs and tests.
struct StepOutput {
    double t_s = 0;
    Vec3 device_m = Vec3::Zero(), proxy_m = Vec3::Zero(), force_N = Vec3::Zero();
    bool contact = false;
    std::uint32_t face = 0;
    std::uint32_t buttons = 0;
    bool cut = false;  // the scalpel changed the mesh in this step
    double stepTime_us = 0;
};

struct LoopStats {
    LatencyHistogram stepTime_us{0.1, 20'000};
    LatencyHistogram periodError_us{0.1, 20'000};  // real-time mode: how late each step started
    long steps = 0, contactSteps = 0, overruns = 0, nonFiniteEvents = 0;
    bool watchdogTripped = false;  // latched by a non-finite force or state: force stays zero
    long cutEvents = 0;            // steps in which the scalpel changed the mesh
    LatencyHistogram cutTime_us{0.1, 100'000};  // the cut and the updates it needs (tree, stepper, proxy)
    double maxForce_N = 0;
    double wallTime_s = 0;
};

/// What the renderer reads: the deformed positions, the faces when a cut changed them, and the tool state.
struct Snapshot {
    std::vector<Vec3> positions;
    std::vector<mesh::Face> faces;  // copied only when topologyVersion changes
    std::vector<mesh::FaceUvs> uvs;
    long topologyVersion = -1;
    Vec3 device_m = Vec3::Zero(), proxy_m = Vec3::Zero(), force_N = Vec3::Zero();
    bool contact = false;
    long step = 0;
    // The loop's health, for the viewer's panel: reading LoopStats from another thread would race.
    double stepTime_us = 0;     // of the step that published this
    double maxStepTime_us = 0;  // the slowest step since the previous snapshot
    double stableStep_s = 0;    // the integrator's stable step on the current model
    int substeps = 1;
    long overruns = 0, cutEvents = 0, contactSteps = 0;
    bool watchdogTripped = false, paused = false;
};

struct LoopCommand {
    enum class Kind {
        SetCouplingStiffness, SetCouplingDamping, SetMaxForceScale, SetCutThreshold, ResetModel, ResetWatchdog, Pause, Resume,
        // Material, live: each multiplies the model's current values by `value` (> 0) and re-prepares the
        // stepper for the new stable step. That allocates, like a cut: a user's action, not steady state.
        ScaleMass, ScaleStructuralStiffness, ScaleStructuralDamping, ScalePositioningStiffness, ScalePositioningDamping
    } kind;
    double value = 0;
};

class HapticLoop {
public:
    /// The loop keeps references to the model, the faces and the device; they must outlive it.
    HapticLoop(physics::MassSpringModel& model, std::span<const mesh::Face> faces, Device& device, LoopConfig config = {});
    /// A loop whose tool can cut the organ (when config.cutThreshold_N is finite). Cut events change
    /// the organ's arrays, so nothing else may read them while the loop runs: the renderer reads snapshots.
    HapticLoop(cutting::CutModel& organ, Device& device, LoopConfig config = {});
    ~HapticLoop();
    HapticLoop(const HapticLoop&) = delete;
    HapticLoop& operator=(const HapticLoop&) = delete;

    /// One haptic step. Allocation-free, lock-free, no I/O.
    StepOutput step() noexcept;

    /// Steps as fast as it can on simulated time; `observer` sees every step.
    void runSimulated(long steps, const std::function<void(const StepOutput&)>& observer = {});
    /// Starts a thread that steps at rate_hz on the wall clock, until stop() or max_steps (negative: no limit).
    /// `observer` runs on that thread: it must not block or allocate. A device with its own servo loop
    /// (Device::servoClock) steps the loop from its servo thread instead, at its own rate; false (with
    /// `error`) when that servo cannot start.
    bool start(long max_steps = -1, std::function<void(const StepOutput&)> observer = {});
    bool start(long max_steps, std::function<void(const StepOutput&)> observer, std::string& error);
    void stop();
    bool running() const { return running_.load(std::memory_order_acquire); }

    TripleBuffer<Snapshot>& snapshots() { return snapshots_; }
    SpscQueue<LoopCommand, 64>& commands() { return commands_; }
    /// Read after the run (or from the loop's own thread).
    const LoopStats& stats() const { return stats_; }
    const GodObjectProxy& proxy() const { return proxy_; }
    const collision::Bvh& bvh() const { return bvh_; }
    collision::SurfaceView surface() const { return {model_.nodes.position, faces_}; }
    /// The cutter's counts (cut points, added vertices and faces, length), if this loop can cut.
    const cutting::ProgressiveCutter* cutter() const { return cutter_ ? &*cutter_ : nullptr; }
    /// Bumped by every cut that changed the mesh.
    long topologyVersion() const { return topologyVersion_; }
    double time_s() const { return static_cast<double>(stepIndex_) / config_.rate_hz; }

private:
    void initialise();
    void applyPendingCommands() noexcept;
    /// Brings the tree, the stepper and the proxy up to date after the cutter changed the mesh.
    void afterTopologyChange();
    void scaleMaterial(LoopCommand::Kind kind, double factor) noexcept;
    void publishSnapshot(const StepOutput& out);
    void threadMain(long max_steps, std::function<void(const StepOutput&)> observer);

    physics::MassSpringModel& model_;
    std::span<const mesh::Face> faces_;
    cutting::CutModel* organ_ = nullptr;  // set when the tool can cut; owns model_ and the faces
    Device& device_;
    LoopConfig config_;
    physics::Stepper stepper_;
    collision::Bvh bvh_;
    mesh::VertexFaces ownTopology_;                // the faces around each vertex, when no CutModel keeps them
    const mesh::VertexFaces* topology_ = nullptr;
    std::optional<cutting::ProgressiveCutter> cutter_;
    long topologyVersion_ = 0;
    double lastForce_N_ = 0;                       // the force of the previous step, which decides whether to cut
    GodObjectProxy proxy_;
    LoopStats stats_;
    TripleBuffer<Snapshot> snapshots_;
    SpscQueue<LoopCommand, 64> commands_;
    long stepIndex_ = 0;
    double maxForceScale_ = 1;
    bool paused_ = false;
    bool realtime_ = false;
    double maxStepSinceSnapshot_us_ = 0;
    double preparedCouplingStiffness_ = 0;  // the stable step allows for a coupling up to this stiff
    std::atomic<bool> running_{false}, stopRequested_{false};
    std::thread thread_;
    ServoClock* servo_ = nullptr;  // set while a device's servo drives the loop
    // The driven loop's own bookkeeping (what threadMain keeps on its stack).
    long servoSteps_ = 0, servoMaxSteps_ = -1;
    std::chrono::steady_clock::time_point servoBegin_{}, servoLast_{};
    std::function<void(const StepOutput&)> servoObserver_;
};

}  // namespace hapticut::haptics
