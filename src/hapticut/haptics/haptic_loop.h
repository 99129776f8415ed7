// One haptic step (DESIGN "The loop"): devices -> proxies -> cut -> coupling forces -> tissue -> devices,
// for one or two hands, each a device with its own tool and proxy, pressing the same organ in the same
// step. When steps happen is loop_scheduler.h's business; what the renderer sees, snapshot_publisher.h's.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <thread>
#include <vector>

#include "hapticut/collision/bvh.h"
#include "hapticut/common/error.h"
#include "hapticut/common/latency_histogram.h"
#include "hapticut/common/result.h"
#include "hapticut/common/spsc_queue.h"
#include "hapticut/cutting/fracture.h"
#include "hapticut/cutting/progressive_cutter.h"
#include "hapticut/haptics/contact_footprint.h"
#include "hapticut/haptics/device.h"
#include "hapticut/haptics/physics_worker.h"
#include "hapticut/haptics/proxy.h"
#include "hapticut/haptics/snapshot_publisher.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/solver_stats.h"

namespace hapticut::haptics {

struct LoopConfig {
    double rate_hz = 1000;  // 1 kHz (R7); up to 10 kHz
    /// Auto keeps the thesis's RK4 where one step per period is stable (the 1,619 heart) and integrates
    /// implicitly where RK4 would need substeps (finer and badly shaped organs); see resolveScheme.
    physics::Scheme scheme = physics::Scheme::Auto;
    physics::SolverSettings solver{};  // the implicit scheme's linear solve
    /// Multi: the physics on its own thread at the rate it can hold (physics_worker.h) while this loop
    /// keeps its period against the latest surface. Auto: multi-rate from the start for organs of more
    /// than multiRateAbove_nodes nodes; otherwise single-rate until, on the wall clock, the physics takes
    /// more than half the period in kSlowPhysicsSteps steps within a second, and multi-rate from then on.
    enum class PhysicsRate { Single, Multi, Auto } physicsRate = PhysicsRate::Auto;
    std::size_t multiRateAbove_nodes = 40'000;  // about 80,000 triangles
    // Multi-rate: a physics step simulates as long as the previous one took, at most this long (the
    // steps after it simulate the rest, up to this long again; beyond that the physics falls behind, and
    // the report says so). Implicit steps are stable at any length, and a
    // step of a large region lasts tens of milliseconds: on the 1,000,000 heart a press wakes 40,000 nodes
    // and a scalpel 50,000, and their steps took 30-45 ms. Capped at 20 ms they simulated 20 ms each and the
    // tissue fell to 0.96 of real time in the press and 0.75 under the scalpel, dragged on by the hand.
    double maxPhysicsStep_s = 0.05;
    int simulatedPhysicsEvery = 4;           // multi-rate in simulated time: a physics step every this many periods
    double couplingStiffness_N_per_m = 400;  // k_h of the virtual spring between proxy and device; live changes up to
                                             // this value. 400 N/m keeps RK4 at one step per ms on the 1,619 heart.
    double couplingDamping_Ns_per_m = 0.3;   // b_h on the device velocity, only while in contact
    double rampTime_s = 0.5;                 // force fades in over this long after start and after a watchdog reset
    /// On the wall clock a step that starts this many periods late or more follows a stall (the process
    /// stopped, a servo tick held up): it sends no force and the force ramps back in, since the hand has
    /// moved on from where the last force was computed.
    double stallPeriods = 3;
    double stallRampTime_s = 0.1;  // the force sent fades back in over this long after a stall
    /// The SCHED_FIFO priority the haptic thread asks for on the wall clock (RealTimeScheduler), so that
    /// no normal thread (the physics, the renderer, the rest of the machine) delays its steps; 0: the
    /// normal scheduler. Below the 50 of a real-time kernel's interrupt threads, which serve the devices.
    int hapticThreadPriority = 40;
    int snapshotEvery = 8;     // publish positions for the renderer every N steps (125 Hz)
    bool activeRegion = true;  // integrate only the tissue near the tool (Stepper::setActiveRegion)
    /// The tool cuts while its force is above this (R14): the scalpel's threshold; the probe's is infinite.
    /// The single-device constructor's tool; a Hand carries its own, which SetCutThreshold changes.
    double cutThreshold_N = std::numeric_limits<double>::infinity();
    /// The single-device constructor's tool tip: its load spreads over this radius (contact_footprint.h);
    /// 0: the thesis's point contact on the touched triangle (R9). A Hand carries its own.
    double tipRadius_m = 0;
    ProxyParams proxy{};
    cutting::CutterParams cutter{};
    /// The tissue's fracture toughness (cutting/fracture.h) for blades whose Hand gives none; empty:
    /// each blade's from its tool's threshold (toughnessFromThreshold).
    std::optional<double> toughness_J_per_m2{};
    /// Volume (physics/volume_pressure.h): the closed organ's enclosed volume kept by a pressure of this
    /// bulk modulus; 0: off. Single-rate only, over the whole organ (a pressure acts everywhere, so the
    /// active region is off): a cost of the organ's size each step.
    double bulkModulus_Pa = 0;
    /// Provot's strain limit (physics/strain_limit.h): springs stretched more than this share of their
    /// rest length are pulled back after every physics step; 0: off. The opened wound's springs, whose
    /// rest lengths a cut shortens by 10%, are held too: a limit under 0.11 closes wounds a little.
    double strainLimit = 0;
};

/// How far, as a share of its tip's radius, a contact slides over the tissue before its footprint is
/// built again: a slide of d moves about 2 d / r of the load, 10% here.
inline constexpr double kFootprintSlide = 0.05;
/// A footprint is built over as many steps as it needs, this many faces a step (ContactFootprint::advance),
/// while the tool loads the footprint it had. A 7 mm tip on the 100,000-triangle heart walks about 1,300
/// faces, so it is built in the step that asks; on the 1,000,000 heart it walks 8,000-16,000, which took
/// a step 0.3-0.7 ms (more on a cold cache than in `bench`) whole, an overrun together with a frame.
inline constexpr std::size_t kFootprintFacesPerStep = 2048;
/// In real time, fewer where a face has lately cost more than this a step: under a scalpel on the
/// 1,000,000 heart the 2,048 faces took 200-340 µs in the slowest steps (a cold cache after a cut), the
/// most of any part of those steps after a frame's part. In simulated time every step takes
/// kFootprintFacesPerStep, so a run does not depend on the machine.
inline constexpr double kFootprintBudget_us = 150;
inline constexpr std::size_t kMinFootprintFaces = 256;
/// The faces a footprint's build takes in a step: as many as `ns_per_face` (what a face cost lately) lets
/// into kFootprintBudget_us, within kMinFootprintFaces and kFootprintFacesPerStep; kFootprintFacesPerStep
/// while that cost is unknown (0).
std::size_t footprintFacesPerStep(double ns_per_face);
/// The collision tree's margin as a share of the organ's mean edge (Bvh::setMargin): wide enough that the
/// nodes a step moves by microns stay in their boxes, narrow enough that queries meet few more boxes.
/// Measured on the 100,000 and 1,000,000 hearts: 0.1 and 0.3 edges left as many overruns in a real-time
/// stroke as this, and 0.1 made the proxy's update 10-20% slower.
inline constexpr double kTreeMarginPerEdge = 0.03;

/// Multi-rate in real time: a physics frame comes in a part of at most kFramePartNodes nodes at a time,
/// and a haptic step takes further parts, up to kFrameNodesPerStep nodes, while the parts it took moved
/// fewer than kFrameFacesPerStep faces out of their boxes in the collision tree. On the 1,000,000-triangle
/// heart a part costs about 30 µs to take in, and each face it moves about 70 ns to refit: a frame that
/// moves the surface still comes in a part a step, and a quiet one, whose nodes stay within their boxes,
/// twice as fast. A press held on that heart moves 60,000 nodes a frame, which took 30 ms to come in a
/// part a step while the physics, its other frame made, waited for it.
inline constexpr std::size_t kFramePartNodes = 2048;
inline constexpr std::size_t kFrameNodesPerStep = 4096;
inline constexpr std::size_t kFrameFacesPerStep = 2048;
/// A part is smaller where taking nodes in has lately cost more than this a part: under a scalpel on
/// the 1,000,000 heart a part of 2,048 nodes moved 9,000-12,000 faces out of their boxes and took
/// 400-800 µs to come in on a slow day (the refit most), and with the tool's coupling and a cut event in
/// the same step some steps overran.
inline constexpr double kFramePartBudget_us = 400;
inline constexpr std::size_t kMinFramePartNodes = 256;
/// And a part has only what is left of this share of the period, counted from the step's start, after
/// the step's other work (a cut event, the proxies, the tool's coupling and its footprint): those came
/// together with a part in the steps that still overran under the scalpel on the 1,000,000 heart.
inline constexpr double kStepWorkShare = 0.6;
/// The nodes of a frame's next part: as many as `intake_ns_per_node` (what taking a node in has lately
/// cost, its share of the tree's refit and of the proxies' following included) lets into `budget_us`,
/// within kMinFramePartNodes and kFramePartNodes; kFramePartNodes while that cost is unknown (0).
std::size_t framePartNodes(double intake_ns_per_node, double budget_us = kFramePartBudget_us);

/// How many physics steps within a second may take more than half the period before an Auto loop
/// turns multi-rate.
inline constexpr int kSlowPhysicsSteps = 20;

/// The force a hand may gain per second unless its Hand says otherwise: 1.5 N in a millisecond is a
/// jolt, a press that reaches the Touch's 3.3 N in 2 ms is not.
inline constexpr double kDefaultMaxForceRate_N_per_s = 1500;

/// One hand on the model: a device and the tool it holds, with that device's safety limits.
struct Hand {
    Device* device = nullptr;
    double cutThreshold_N = std::numeric_limits<double>::infinity();  // the tool's (R14); infinite: it never cuts
    /// The tool's tip: its load spreads over the surface within this radius (contact_footprint.h), so a
    /// press feels the same on any mesh finer than the tip; 0: the thesis's point contact (R9).
    double tipRadius_m = 0;
    /// The tissue's fracture toughness for this tool's blade (cutting/fracture.h); empty: from the
    /// threshold (toughnessFromThreshold), so a tool file without it keeps its feel.
    std::optional<double> toughness_J_per_m2{};
    double maxForce_N = std::numeric_limits<double>::infinity();  // below the device's own maximum, if lower
    double maxForceRate_N_per_s = kDefaultMaxForceRate_N_per_s;   // how fast the force sent may grow
    /// This hand's coupling k_h and b_h (a scene's [[devices]] entry); empty: the loop's, which the
    /// panel changes live.
    std::optional<double> couplingStiffness_N_per_m{}, couplingDamping_Ns_per_m{};
    /// A hand that touches only while its device's first button is held (the viewer's mouse): with the
    /// button up its proxy goes wherever the device goes, through the tissue or not, and it neither
    /// presses nor cuts, so a cursor that jumps (a view change, a switch of hands) drags nothing.
    bool touchesOnlyWhileButtonHeld = false;
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
    /// overruns: steps that took longer than a period, and periods in which no step started at all.
    long steps = 0, contactSteps = 0, overruns = 0, nonFiniteEvents = 0;
    long missedPeriods = 0;        // periods in which no step started (counted in overruns too)
    long stalls = 0;               // gaps of LoopConfig::stallPeriods or more: force zeroed and ramped back in
    long rateLimitedSteps = 0;     // steps in which a hand's force was held back by its maximum force rate
    long contactNodesMax = 0;      // the most nodes a tool's load spread over in one step
    long footprintCutSteps = 0;    // steps whose footprint held more nodes than a tool can load (cut to fit)
    bool watchdogTripped = false;  // latched by a non-finite force or state: force stays zero
    long cutEvents = 0;            // steps in which the scalpel changed the mesh
    LatencyHistogram cutTime_us{0.1, 100'000};   // the cut and the updates it needs (tree, stepper, proxy)
    LatencyHistogram syncTime_us{0.1, 100'000};  // multi-rate: cuts and edits copied into the physics' copy
    double maxForce_N = 0;                       // the largest force sent to any hand
    double wallTime_s = 0;
    physics::SolverStats solver;    // the implicit scheme's solves; none for an explicit one
    long physicsSteps = 0;          // equal to steps in a single-rate loop
    long multiRateFromStep = -1;    // the step from which the physics ran on its own thread; -1: never
    long multiRateSwitchSteps = 0;  // Auto: steps taken, the tissue held still, while the physics' copy was made
    double physicsTime_s = 0;       // simulated by them
    // How long each physics step took to compute on the wall clock, and the wall time left unsimulated
    // because multi-rate steps fell behind by more than LoopConfig::maxPhysicsStep_s, more than the steps
    // after one may carry (PhysicsWorker::start).
    LatencyHistogram physicsStepTime_us{10, 200'000};
    double physicsTimeLost_s = 0;
    long toolsOutOfReach = 0;  // multi-rate: tools a physics step left out, as they named nodes its copy lacked
    bool volumeKept = false;   // LoopConfig::bulkModulus_Pa took effect (a closed organ, single-rate)
};

struct LoopCommand {
    enum class Kind {
        SetCouplingStiffness,
        SetCouplingDamping,
        SetMaxForceScale,
        SetCutThreshold,
        SetTipRadius,
        ResetModel,
        ResetWatchdog,
        Pause,
        Resume,
        // Material, live: each multiplies the model's current values by `value` (> 0) and re-prepares the
        // stepper for the new stable step. That allocates, like a cut: a user's action, not steady state.
        ScaleMass,
        ScaleStructuralStiffness,
        ScaleStructuralDamping,
        ScalePositioningStiffness,
        ScalePositioningDamping
    } kind;
    double value = 0;
    int hand = 0;  // SetCutThreshold, SetTipRadius: whose tool
};

class HapticLoop {
public:
    /// One device on an organ, with config.cutThreshold_N as its tool's threshold. The loop keeps
    /// references to the organ and the device; they must outlive it. Cut events change the organ's
    /// arrays, so nothing else may read them while the loop runs: the renderer reads snapshots.
    HapticLoop(cutting::CutModel& organ, Device& device, LoopConfig config = {});
    /// One or two hands on an organ, each with its own tool, proxy and limits. Only one tool cuts at a
    /// time: a cut in progress belongs to the hand that started it. An error for no hands, too many, a
    /// hand without a device, or a rate outside 1 Hz - 100 kHz.
    static Result<std::unique_ptr<HapticLoop>, Error> create(cutting::CutModel& organ, std::span<const Hand> hands,
                                                             LoopConfig config = {});
    /// Leaves every device at zero force.
    ~HapticLoop();
    HapticLoop(const HapticLoop&) = delete;
    HapticLoop& operator=(const HapticLoop&) = delete;

    /// One haptic step. Allocation-free, lock-free, no I/O.
    StepOutput step() noexcept;

    TripleBuffer<Snapshot>& snapshots() { return snapshots_.buffer(); }
    SpscQueue<LoopCommand, 64>& commands() { return commands_; }
    /// Read after the run (or from the thread that steps the loop).
    const LoopStats& stats() const { return stats_; }
    const GodObjectProxy& proxy(int hand = 0) const { return hands_[static_cast<std::size_t>(hand)].proxy; }
    int handCount() const { return static_cast<int>(hands_.size()); }
    /// The coupling stiffness hand `hand` gets: its own or the loop's, capped by its device's maximum stiffness.
    double couplingStiffness_N_per_m(int hand) const;
    const collision::Bvh& bvh() const { return bvh_; }
    collision::SurfaceView surface() const { return {model_.nodes.position, faces_}; }
    /// The cutter's counts (cut points, added vertices and faces, length).
    const cutting::ProgressiveCutter& cutter() const { return cutter_; }
    /// Bumped by every cut that changed the mesh.
    long topologyVersion() const { return topologyVersion_; }
    double time_s() const { return static_cast<double>(stepIndex_) / config_.rate_hz; }
    double rate_hz() const { return config_.rate_hz; }
    int hapticThreadPriority() const { return config_.hapticThreadPriority; }
    /// The scheme the tissue is integrated with: config.scheme, with Auto resolved for this organ.
    physics::Scheme scheme() const;
    /// The nodes the latest step moved (the active region's; every node without one).
    std::span<const std::uint32_t> movedNodes() const {
        return worker_ ? std::span<const std::uint32_t>(frameNodes_) : stepper_.movedNodes();
    }
    /// Substeps per period of the scheme on the current organ (1 for the implicit one).
    int substeps() const;
    /// The volume the closed organ's anchors enclose, which the pressure keeps (0 with volume off).
    double restVolume_m3() const { return restVolume_m3_; }
    /// Whether the physics runs apart from this loop (LoopConfig::physicsRate).
    bool multiRate() const { return worker_ != nullptr; }

    // For schedulers (loop_scheduler.h), from the thread that steps the loop or while it is stopped.
    /// On the wall clock a step that overruns its period withholds its force (the watchdog).
    void setRealtime(bool on);
    /// How late the coming step starts: counted in the period error, every period it missed counts as
    /// an overrun, and a stall (LoopConfig::stallPeriods) zeroes its force and ramps it back in.
    void recordLateness(double late_us) noexcept;
    void addWallTime(double seconds) { stats_.wallTime_s += seconds; }
    void zeroAllForces() noexcept;
    /// The devices' own servo loops, in hand order; empty when no device has one.
    std::vector<ServoClock*> servoClocks() const;

private:
    HapticLoop(cutting::CutModel& organ, std::span<const Hand> hands, LoopConfig config);

    /// A hand's state in the loop; the vector holding them is sized once, at construction.
    struct HandState {
        Hand setup;
        GodObjectProxy proxy;
        double stiffnessCap_N_per_m = std::numeric_limits<double>::infinity();
        double lastForce_N = 0;  // the force of the previous step, which decides whether to cut
        // The crack this hand's blade is opening (Mahvash & Hayward): its tip, the way it last ran, and
        // the force the tissue ahead resists with along the surface, which replaces the coupling's
        // component along the surface while the blade cuts (across it the proxy still supports it).
        bool cracking = false;
        bool bladeAhead = false;  // the blade presses on into uncut tissue (not back in its own cut)
        Vec3 crackTip_m = Vec3::Zero(), crackDirection = Vec3::Zero(), crackNormal = Vec3::Zero();
        Vec3 fractureForce_N = Vec3::Zero();
        Vec3 sentForce_N = Vec3::Zero();    // what the device was last told, for the force-rate limit
        long lastContactStep = -1'000'000;  // the last step in which it touched
        // The footprint its tool's load spreads over: where on the rest surface it was built, for
        // which topology and tip, and the dent under the tip the mesh cannot show (loadTissue).
        Vec3 footprintAt_m = Vec3::Zero();
        long footprintTopology = -1;
        double footprintRadius_m = 0, subgrid_m_per_N = 0;
    };
    /// What a step knows about each hand as it goes through its phases.
    struct HandFrame {
        DeviceSample sample;
        bool deviceOk = false;  // the sample is finite
        bool touching = false;  // the proxy is held off the device by the surface: the hand presses
        Vec3 force_N = Vec3::Zero();
    };
    using Frame = std::array<HandFrame, kMaxHands>;

    void initialise(std::span<const Hand> hands);
    // The phases of step(), in order.
    void applyPendingCommands() noexcept;
    void readDevices(Frame& frame, StepOutput& out) noexcept;
    void moveProxies(Frame& frame) noexcept;
    void cut(const Frame& frame, StepOutput& out) noexcept;
    /// The cutting hand's blade `blade`, which goes into the tissue at `blade_m`: its crack advanced by the
    /// fracture rule and the resistance it feels; the crack tip the cut must now reach, if it moved.
    std::optional<Vec3> resistBlade(HandState& hand, std::size_t h, const DeviceSample& blade, const Vec3& blade_m,
                                    const Vec3& normal, double depth_m) noexcept;
    /// Where a blade with its tip at `tip_m` and its handle along `axis` goes into the tissue: along the
    /// surface, the point the fracture rule follows. The tip itself for a blade without an axis (one taken
    /// as square to the surface, whose projection onto the surface is its tip's).
    static Vec3 bladeAtSurface(const Vec3& tip_m, const Vec3& axis,
                               const cutting::ProgressiveCutter::BladeProjection& blade) noexcept;
    void endCrack(HandState& hand) noexcept;
    void coupleTools(Frame& frame, double t_s) noexcept;
    void advanceTissue(Frame& frame) noexcept;
    /// Multi-rate: hands the tools to the physics, steps it in simulated time, and takes in its frames.
    void advanceMultiRate(Frame& frame) noexcept;
    /// Volume: the pressure of the enclosed volume into the nodes' external forces (zero when off).
    void pressVolume() noexcept;
    /// Multi-rate: the frames the physics made so far, into the model, the tree and the proxies, in real
    /// time a part at a time, as kFramePartNodes says. True when every frame made so far is in.
    bool takeFrames(Frame& frame) noexcept;
    /// What a frame's next part may cost this step, at `now`: kFramePartBudget_us, or what the step's other
    /// work left of kStepWorkShare of the period (framePartNodes gives kMinFramePartNodes when it left none).
    double partBudget_us(std::chrono::steady_clock::time_point now) const noexcept;
    /// What a node of the next part is taken to cost: the running mean, or what the `taken` nodes of this
    /// step's parts cost (`intake`, all of them), whichever is more.
    double partCost_ns_per_node(std::size_t taken, std::chrono::steady_clock::duration intake) const noexcept;
    /// Multi-rate, with the physics held: the edits and cuts made since it was last held, into its copy.
    void syncWorker() noexcept;
    /// Starts the physics' own copy and, on the wall clock, its thread, for the steps from `fromStep`.
    void startMultiRate(long fromStep);
    /// A copy of the organ and the stepper for the physics to step on its own.
    std::unique_ptr<PhysicsWorker> makeWorker() const;
    /// Makes `worker` the physics' own copy and, on the wall clock, starts its thread, owing it the
    /// `behind_s` the tissue stood still before.
    void adoptWorker(std::unique_ptr<PhysicsWorker> worker, long fromStep, double behind_s = 0);
    /// Multi-rate leaves volume off: the physics' copy has no faces to take a volume of.
    void dropVolumeForMultiRate() noexcept;
    /// Single-rate, Auto, on the wall clock: counts physics steps that took more than half the period,
    /// and turns the loop multi-rate once there are kSlowPhysicsSteps of them within a second.
    void watchPhysicsTime(double physics_us) noexcept;
    /// Auto's switch: copying the organ and preparing the physics' own stepper takes tens of milliseconds
    /// (28 ms for 50,000 triangles), so a thread of its own makes the copy while this one keeps its rate
    /// with the tissue held still: no physics step, no cut, edits queued, so that nothing the copy reads
    /// changes under it. The tools' contacts, which this thread writes every step, are not copied.
    void beginMultiRateSwitch() noexcept;
    /// While switching: takes the copy once it is made. False while it is still being made.
    bool finishMultiRateSwitch() noexcept;
    /// The nodes hand `hand`'s tool loads this step, into `tool`: its tip's footprint (built again only
    /// as the contact slides) or the thesis's triangle. Returns the footprint's subgrid compliance, m/N.
    /// While a new footprint is being built, the tool loads the last one for the same tip (through cuts
    /// too), else the touched triangle. One build is under way at a time (footprintBuilder_).
    double loadTissue(std::size_t h, physics::PointSpring& tool, bool wasActive) noexcept;
    /// Takes the footprint under way a step further: in real time as many faces as footprintFacesPerStep
    /// lets in, at what a face has cost lately. True once it is whole.
    bool advanceFootprint(const collision::SurfaceView& view) noexcept;
    /// Multi-rate: the tool's force with its held point carried `ahead_s` on at its nodes' velocities.
    Vec3 forceAhead(const physics::PointSpring& tool, double ahead_s) const;
    /// An edit to the model: now in a single-rate loop, and in a multi-rate one once the physics is held.
    void editModel(const ModelEdit& edit) noexcept;
    void applyEdit(const ModelEdit& edit) noexcept;
    /// The collision tree follows the tissue: the faces round the nodes the step moved out of their boxes.
    void refitMovedFaces() noexcept;
    /// Of `nodes`, those that have moved farther than the tree's margin from where its boxes last saw
    /// them: brings treePositions_ up to date for them and appends the faces round them to movedFaces_.
    /// False when the whole tree is better refitted (a quarter of the organ moved, or the list would
    /// outgrow its room).
    bool gatherFacesRound(std::span<const std::uint32_t> nodes) noexcept;
    /// Every box from every node where it is now.
    void refitWholeTree() noexcept;
    /// What the tree's boxes are computed from (see treePositions_).
    collision::SurfaceView treeSurface() const { return {treePositions_, faces_}; }
    void sendForces(const Frame& frame, StepOutput& out) noexcept;
    /// Counts the step, publishes its snapshot when one is due and records the step's time from `start`,
    /// the publication included; `elapsed_us` is its time up to the forces, which the snapshot carries.
    void finishStep(StepOutput& out, std::chrono::steady_clock::time_point start, double elapsed_us) noexcept;

    /// Whether hand h's proxy is in contact and held off its device this step.
    bool touching(const Frame& frame, std::size_t h) const;
    /// Whether hand h is let go this step: a hand that touches only while its button is held, without it.
    bool letGo(const Frame& frame, std::size_t h) const;
    void tripWatchdog() noexcept;
    /// Brings the tree, the stepper, the proxies and the snapshots' face log up to date after a cut.
    void afterTopologyChange();
    void publishSnapshot(const StepOutput& out);

    cutting::CutModel& organ_;
    physics::MassSpringModel& model_;
    std::span<const mesh::Face> faces_;
    std::vector<HandState> hands_;
    int cuttingHand_ = -1;  // the hand whose cut is in progress
    LoopConfig config_;
    physics::Stepper stepper_;
    physics::SolveReport lastSolve_;         // the latest step's, for the snapshot
    double lastPhysicsStep_s_ = 0;           // how long the latest physics step took, for the snapshot
    std::vector<std::uint32_t> movedFaces_;  // the faces round the nodes the latest step moved, for the refit
    // Each node where the tree's boxes last saw it. The boxes are grown by a margin (Bvh::setMargin), so
    // they hold every face while its corners stay within the margin of these: most of an awake region
    // moves microns a step, and only the nodes that leave their boxes cost a refit.
    std::vector<Vec3> treePositions_;
    std::unique_ptr<PhysicsWorker> worker_;  // multi-rate only
    // Auto's switch to multi-rate (beginMultiRateSwitch): the thread making the physics' copy, the copy,
    // and whether it is done (written by that thread last).
    std::thread workerBuilder_;
    std::unique_ptr<PhysicsWorker> builtWorker_;
    std::atomic<bool> workerBuilt_{false};
    bool switchingToMultiRate_ = false;
    std::vector<std::uint32_t> frameNodes_;     // multi-rate: the nodes the frames taken this step moved
    std::array<ModelEdit, 16> pendingEdits_{};  // multi-rate: edits waiting for the physics to be held
    int pendingEditCount_ = 0;
    std::vector<std::uint32_t> pendingNodes_, pendingSprings_;  // multi-rate: what cuts changed since the last sync
    bool pendingSync_ = false;
    long lastFrameStep_ = 0;              // multi-rate: the step whose present the latest frame's state is
    std::size_t frameCursor_ = 0;         // multi-rate: how many of the frame being taken in are in
    double frameIntake_ns_per_node_ = 0;  // multi-rate in real time: what a node's intake cost lately (framePartNodes)
    double footprint_ns_per_face_ = 0;    // in real time: what a footprint's face cost lately (footprintFacesPerStep)
    // When this step began: its later work has what is left of kStepWorkShare of the period.
    std::chrono::steady_clock::time_point stepStart_{};
    int slowPhysicsSteps_ = 0;  // watchPhysicsTime's count in the current second
    long slowWindowStart_ = 0;
    collision::Bvh bvh_;
    ContactFootprint footprint_;
    // The hand whose footprint footprint_ is building (-1: none), and for which surface and tip it began.
    int footprintBuilder_ = -1;
    long footprintBuildTopology_ = -1;
    double footprintBuildRadius_m_ = 0;
    Vec3 footprintBuildAt_m_ = Vec3::Zero();  // on the rest surface
    cutting::ProgressiveCutter cutter_;
    long topologyVersion_ = 0;
    double rampStart_s_ = 0;  // forces fade in from here: the start, or a watchdog reset
    // The force sent fades back in from here after a stall (LoopConfig::stallRampTime_s).
    double stallRampStart_s_ = -std::numeric_limits<double>::infinity();
    bool stalled_ = false;      // recordLateness saw a stall before the coming step
    bool stallToShow_ = false;  // the coming snapshot carries a new stall: published whatever snapshotEvery says
    LoopStats stats_;
    SnapshotPublisher snapshots_;
    SpscQueue<LoopCommand, 64> commands_;
    long stepIndex_ = 0;
    double maxForceScale_ = 1;
    bool paused_ = false;
    bool realtime_ = false;
    double maxStepSinceSnapshot_us_ = 0;
    double preparedCouplingStiffness_ = 0;  // the stable step allows for a coupling up to this stiff
    bool volumeOn_ = false;                 // LoopConfig::bulkModulus_Pa on a closed organ, single-rate
    double restVolume_m3_ = 0;              // enclosed by the anchors (the organ unloaded), after the latest cut
};

}  // namespace hapticut::haptics
