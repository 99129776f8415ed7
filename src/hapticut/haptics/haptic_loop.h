// The haptic loop (DESIGN "The loop"): device -> proxy -> force -> tissue -> physics -> device, at
// 1 kHz by default, in simulated time or in its own real-time thread; one or two hands, each a device
// with its own tool and proxy, pressing the same model in the same step.
#pragma once

#include <array>
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
    double rampTime_s = 0.5;                   // force fades in over this long after start and after a watchdog reset
    int snapshotEvery = 8;                     // publish positions for the renderer every N steps (125 Hz)
    bool activeRegion = true;                  // integrate only the tissue near the tool (Stepper::setActiveRegion)
    /// The tool cuts while its force is above this (R14): the scalpel's threshold; the probe's is infinite.
    /// Only a loop built on a CutModel cuts.
    /// The single-device constructors' tool; a Hand carries its own, which SetCutThreshold changes.
    double cutThreshold_N = std::numeric_limits<double>::infinity();
    ProxyParams proxy;
    cutting::CutterParams cutter;
};

inline constexpr int kMaxHands = physics::kMaxTools;

/// The force a hand may gain per second unless its Hand says otherwise: 1.5 N in a millisecond is a
/// jolt, a press that reaches the Touch's 3.3 N in 2 ms is not.
inline constexpr double kDefaultMaxForceRate_N_per_s = 1500;

/// One hand on the model: a device and the tool it holds, with that device's safety limits.
struct Hand {
    Device* device = nullptr;
    double cutThreshold_N = std::numeric_limits<double>::infinity();  // the tool's (R14); infinite: it never cuts
    double maxForce_N = std::numeric_limits<double>::infinity();      // below the device's own maximum, if lower
    double maxForceRate_N_per_s = kDefaultMaxForceRate_N_per_s;      // how fast the force sent may grow
};

/// What one hand did in one step.
struct HandStep {
    Vec3 device_m = Vec3::Zero(), proxy_m = Vec3::Zero(), force_N = Vec3::Zero();
    bool contact = false;
    std::uint32_t face = 0;
    std::uint32_t buttons = 0;
};

/// What one step did, for logs and tests.
struct StepOutput {
    double t_s = 0;
    std::array<HandStep, kMaxHands> hands{};  // the first handCount are in use
    int handCount = 1;
    bool cut = false;  // a scalpel changed the mesh in this step
    double stepTime_us = 0;

    /// The first hand: the only one in a single-device loop.
    const HandStep& hand() const { return hands[0]; }
};

struct LoopStats {
    LatencyHistogram stepTime_us{0.1, 20'000};
    LatencyHistogram periodError_us{0.1, 20'000};  // real-time mode: how late each step started
    long steps = 0, contactSteps = 0, overruns = 0, nonFiniteEvents = 0;
    long rateLimitedSteps = 0;     // steps in which a hand's force was held back by its maximum force rate
    bool watchdogTripped = false;  // latched by a non-finite force or state: force stays zero
    long cutEvents = 0;            // steps in which the scalpel changed the mesh
    LatencyHistogram cutTime_us{0.1, 100'000};  // the cut and the updates it needs (tree, stepper, proxy)
    double maxForce_N = 0;         // the largest force sent to any hand
    double wallTime_s = 0;
};

/// What the renderer reads: the deformed positions, the faces when a cut changed them, and the tool state.
struct Snapshot {
    std::vector<Vec3> positions;
    std::vector<mesh::Face> faces;  // copied only when topologyVersion changes
    std::vector<mesh::FaceUvs> uvs;
    long topologyVersion = -1;
    std::array<HandStep, kMaxHands> hands{};
    int handCount = 1;
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
    int hand = 0;  // SetCutThreshold: whose tool
};

class HapticLoop {
public:
    /// The loop keeps references to the model, the faces and the device; they must outlive it.
    HapticLoop(physics::MassSpringModel& model, std::span<const mesh::Face> faces, Device& device, LoopConfig config = {});
    /// A loop whose tool can cut the organ (when config.cutThreshold_N is finite). Cut events change
    /// the organ's arrays, so nothing else may read them while the loop runs: the renderer reads snapshots.
    HapticLoop(cutting::CutModel& organ, Device& device, LoopConfig config = {});
    /// One or two hands on an organ, each with its own tool, proxy and limits. Only one tool cuts at a
    /// time: a cut in progress belongs to the hand that started it.
    HapticLoop(cutting::CutModel& organ, std::span<const Hand> hands, LoopConfig config = {});
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
    /// `error`) when that servo cannot start. With two such devices the first one's servo steps the
    /// loop and the second's only exchanges its frame (OpenHaptics runs both in one scheduler).
    bool start(long max_steps = -1, std::function<void(const StepOutput&)> observer = {});
    bool start(long max_steps, std::function<void(const StepOutput&)> observer, std::string& error);
    void stop();
    bool running() const { return running_.load(std::memory_order_acquire); }

    TripleBuffer<Snapshot>& snapshots() { return snapshots_; }
    SpscQueue<LoopCommand, 64>& commands() { return commands_; }
    /// Read after the run (or from the loop's own thread).
    const LoopStats& stats() const { return stats_; }
    const GodObjectProxy& proxy(int hand = 0) const { return hands_[static_cast<std::size_t>(hand)].proxy; }
    int handCount() const { return static_cast<int>(hands_.size()); }
    /// The coupling stiffness hand `hand` gets: the loop's, capped by its device's maximum stiffness.
    double couplingStiffness_N_per_m(int hand) const;
    const collision::Bvh& bvh() const { return bvh_; }
    collision::SurfaceView surface() const { return {model_.nodes.position, faces_}; }
    /// The cutter's counts (cut points, added vertices and faces, length), if this loop can cut.
    const cutting::ProgressiveCutter* cutter() const { return cutter_ ? &*cutter_ : nullptr; }
    /// Bumped by every cut that changed the mesh.
    long topologyVersion() const { return topologyVersion_; }
    double time_s() const { return static_cast<double>(stepIndex_) / config_.rate_hz; }

private:
    /// A hand's state in the loop; the vector holding them is sized once, at construction.
    struct HandState {
        Hand setup;
        GodObjectProxy proxy;
        double stiffnessCap_N_per_m = std::numeric_limits<double>::infinity();
        double lastForce_N = 0;       // the force of the previous step, which decides whether to cut
        Vec3 sentForce_N = Vec3::Zero();  // what the device was last told, for the force-rate limit
    };
    /// Sends each hand its force, rate-limited, and returns in `out` what was sent.
    void sendForces(const std::array<Vec3, kMaxHands>& force, StepOutput& out) noexcept;
    void zeroAllForces() noexcept;
    void initialise(std::span<const Hand> hands);
    void applyPendingCommands() noexcept;
    /// Brings the tree, the stepper and the proxy up to date after the cutter changed the mesh.
    void afterTopologyChange();
    void scaleMaterial(LoopCommand::Kind kind, double factor) noexcept;
    void publishSnapshot(const StepOutput& out);
    void threadMain(long max_steps, std::function<void(const StepOutput&)> observer);

    physics::MassSpringModel& model_;
    std::span<const mesh::Face> faces_;
    cutting::CutModel* organ_ = nullptr;  // set when the tool can cut; owns model_ and the faces
    std::vector<HandState> hands_;
    int cuttingHand_ = -1;  // the hand whose cut is in progress
    LoopConfig config_;
    physics::Stepper stepper_;
    collision::Bvh bvh_;
    mesh::VertexFaces ownTopology_;                // the faces around each vertex, when no CutModel keeps them
    const mesh::VertexFaces* topology_ = nullptr;
    std::optional<cutting::ProgressiveCutter> cutter_;
    long topologyVersion_ = 0;
    // The faces each topology version rewrote or added, kept until every snapshot slot has them, so a
    // slot catches up by copying those faces instead of the whole mesh.
    struct FaceChange {
        long version;
        std::uint32_t face;
    };
    std::vector<FaceChange> faceLog_;
    std::array<long, 3> slotVersion_{};  // the topology version each snapshot slot was last brought to
    double rampStart_s_ = 0;                       // forces fade in from here: the start, or a watchdog reset
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
    std::vector<ServoClock*> servos_;  // set while devices' servos run: the first drives the loop
    // The driven loop's own bookkeeping (what threadMain keeps on its stack).
    long servoSteps_ = 0, servoMaxSteps_ = -1;
    std::chrono::steady_clock::time_point servoBegin_{}, servoLast_{};
    std::function<void(const StepOutput&)> servoObserver_;
};

}  // namespace hapticut::haptics
