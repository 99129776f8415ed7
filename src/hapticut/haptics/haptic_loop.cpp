// The haptic step and its phases.
#include "hapticut/haptics/haptic_loop.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <utility>

#include "hapticut/common/assert.h"
#include "hapticut/common/reserve.h"
#include "hapticut/haptics/force_safety.h"
#include "hapticut/mesh/adjacency.h"
#include "hapticut/mesh/surface_mesh.h"
#include "hapticut/physics/stability.h"
#include "hapticut/physics/volume_pressure.h"

namespace hapticut::haptics {

using Clock = std::chrono::steady_clock;

namespace {
/// How many items that lately cost `ns_per_item` each fit into `budget_us`, within [least, most]; `most`
/// while that cost is unknown (0).
std::size_t itemsWithinBudget(double ns_per_item, double budget_us, std::size_t least, std::size_t most) {
    if (!(ns_per_item > 0)) return most;
    const double fit = 1e3 * budget_us / ns_per_item;
    return static_cast<std::size_t>(std::clamp(fit, static_cast<double>(least), static_cast<double>(most)));
}

/// A running mean of what an item costs, which follows the tissue and the machine within a few samples.
void followCost(double& mean_ns, double sample_ns) {
    mean_ns = mean_ns > 0 ? 0.75 * mean_ns + 0.25 * sample_ns : sample_ns;
}

/// The proxy may use the ray-parity inside test only on a closed surface (no boundary edges).
ProxyParams withClosedFlag(ProxyParams params, std::span<const mesh::Face> faces) {
    const mesh::MeshAdjacency adj = mesh::buildAdjacency(faces);
    params.closedSurface = true;
    for (std::size_t e = 0; e < adj.edges.size() && params.closedSurface; ++e)
        params.closedSurface = adj.facesOfEdge(e).size() == 2;
    return params;
}

std::vector<Hand> oneHand(Device& device, const LoopConfig& config) {
    Hand hand;
    hand.device = &device;
    hand.cutThreshold_N = config.cutThreshold_N;
    hand.tipRadius_m = config.tipRadius_m;
    return {hand};
}
}  // namespace

HapticLoop::HapticLoop(cutting::CutModel& organ, Device& device, LoopConfig config)
    : HapticLoop(organ, oneHand(device, config), config) {}

HapticLoop::HapticLoop(cutting::CutModel& organ, std::span<const Hand> hands, LoopConfig config)
    : organ_(organ),
      model_(organ.model()),
      faces_(organ.mesh().faces),
      config_(config),
      stepper_(config.scheme),
      cutter_(organ, config.cutter) {
    initialise(hands);
}

Result<std::unique_ptr<HapticLoop>, Error> HapticLoop::create(cutting::CutModel& organ, std::span<const Hand> hands,
                                                              LoopConfig config) {
    auto fail = [](std::string message) { return unexpected(Error{{}, 0, std::move(message)}); };
    if (hands.empty() || hands.size() > static_cast<std::size_t>(kMaxHands))
        return fail("a haptic loop takes 1 to " + std::to_string(kMaxHands) + " hands, not " +
                    std::to_string(hands.size()));
    for (const Hand& h : hands)
        if (!h.device) return fail("a hand without a device");
    if (!(config.rate_hz >= 1 && config.rate_hz <= 1e5))
        return fail("a haptic rate of " + std::to_string(config.rate_hz) + " Hz: expected 1 Hz to 100 kHz");
    if (organ.mesh().faces.empty()) return fail("an organ without faces: nothing to touch");
    try {
        auto loop = std::unique_ptr<HapticLoop>(new HapticLoop(organ, hands, config));
        const physics::Stepper& stepper = loop->worker_ ? loop->worker_->stepper() : loop->stepper_;
        if (const std::string why =
                physics::tooManySubsteps(loop->scheme(), loop->substeps(), stepper.stableStep_s(), 1 / config.rate_hz);
            !why.empty())
            return fail(why);
        return loop;
    } catch (const std::bad_alloc&) {
        return fail("out of memory preparing the haptic loop for " + std::to_string(organ.model().nodes.size()) +
                    " nodes");
    }
}

void HapticLoop::initialise(std::span<const Hand> hands) {
    HAPTICUT_ASSERT(!hands.empty() && hands.size() <= static_cast<std::size_t>(kMaxHands));
    const ProxyParams proxyParams = withClosedFlag(config_.proxy, faces_);
    hands_.reserve(hands.size());
    for (const Hand& h : hands) {
        HAPTICUT_ASSERT(h.device != nullptr);
        HandState& state = hands_.emplace_back(HandState{h, GodObjectProxy(proxyParams)});
        state.stiffnessCap_N_per_m = stiffnessCapAt(h.device->maxStiffness_N_per_m(), config_.rate_hz);
    }
    // The stable step allows for every hand pressing the same node at its full coupling.
    preparedCouplingStiffness_ = config_.couplingStiffness_N_per_m;
    double allHands_N_per_m = 0;
    for (const HandState& hand : hands_)
        allHands_N_per_m += hand.setup.couplingStiffness_N_per_m.value_or(preparedCouplingStiffness_);
    stepper_.setToolStiffness(allHands_N_per_m);
    stepper_.setScheme(physics::resolveScheme(config_.scheme, model_, 1 / config_.rate_hz, allHands_N_per_m));
    stepper_.setSolverSettings(config_.solver);
    stepper_.setStrainLimit(config_.strainLimit);
    // A pressure acts on every node of the organ, so with volume on the whole organ is integrated.
    volumeOn_ = config_.bulkModulus_Pa > 0 && organ_.closedBeforeCuts();
    if (volumeOn_) restVolume_m3_ = physics::enclosedVolume(model_.nodes.restPosition, faces_);
    stats_.volumeKept = volumeOn_;
    stepper_.setActiveRegion(config_.activeRegion && !volumeOn_);
    stepper_.prepare(model_);
    if (config_.physicsRate == LoopConfig::PhysicsRate::Multi ||
        (config_.physicsRate == LoopConfig::PhysicsRate::Auto && model_.nodes.size() > config_.multiRateAbove_nodes))
        startMultiRate(0);
    bvh_.setMargin(kTreeMarginPerEdge * mesh::meanEdgeLength(organ_.mesh()));
    reserveTouched(treePositions_, roomToGrow(model_.nodes.size()));
    treePositions_.assign(model_.nodes.position.begin(), model_.nodes.position.end());
    bvh_.build(treeSurface());
    reserveTouched(movedFaces_, 3 * roomToGrow(faces_.size()));
    footprint_.fitTo(model_.nodes.size(), faces_.size());
    for (HandState& hand : hands_) {
        hand.proxy.setTopology(&organ_.vertexFaces());
        // Start the proxy where the device is, or just outside the surface if the device begins inside.
        const Vec3 start = hand.setup.device->read(0).position_m;
        hand.proxy.reset(start + Vec3(0, 0, 1.0));
        hand.proxy.update(start, surface(), bvh_);
    }
    snapshots_.prepare(model_.nodes.position, faces_, organ_.mesh().uvs, organ_.wallFaces(), topologyVersion_,
                       handCount());
}

HapticLoop::~HapticLoop() {
    if (workerBuilder_.joinable()) workerBuilder_.join();
    if (worker_) worker_->stop();
    zeroAllForces();  // a real device must never be left pushing
}

void HapticLoop::startMultiRate(long fromStep) {
    dropVolumeForMultiRate();
    adoptWorker(makeWorker(), fromStep);
}

std::unique_ptr<PhysicsWorker> HapticLoop::makeWorker() const {
    return std::make_unique<PhysicsWorker>(model_, stepper_, config_.scheme, 1 / config_.rate_hz,
                                           config_.maxPhysicsStep_s);
}

void HapticLoop::dropVolumeForMultiRate() noexcept {
    if (!volumeOn_) return;
    volumeOn_ = stats_.volumeKept = false;
    std::fill(model_.nodes.externalForce.begin(), model_.nodes.externalForce.end(), Vec3::Zero());
}

void HapticLoop::adoptWorker(std::unique_ptr<PhysicsWorker> worker, long fromStep, double behind_s) {
    worker_ = std::move(worker);
    frameCursor_ = 0;
    reserveTouched(frameNodes_, roomToGrow(model_.nodes.size()));
    reserveTouched(pendingNodes_, std::size_t{1} << 14);  // what cuts change between two physics steps
    reserveTouched(pendingSprings_, std::size_t{1} << 14);
    stats_.multiRateFromStep = fromStep;
    if (realtime_) worker_->start(behind_s);
}

void HapticLoop::watchPhysicsTime(double physics_us) noexcept {
    if (!realtime_ || worker_ || switchingToMultiRate_ || config_.physicsRate != LoopConfig::PhysicsRate::Auto) return;
    if (static_cast<double>(stepIndex_ - slowWindowStart_) >= config_.rate_hz) {
        slowWindowStart_ = stepIndex_;
        slowPhysicsSteps_ = 0;
    }
    if (physics_us <= 0.5e6 / config_.rate_hz || ++slowPhysicsSteps_ < kSlowPhysicsSteps) return;
    beginMultiRateSwitch();
}

void HapticLoop::beginMultiRateSwitch() noexcept {
    dropVolumeForMultiRate();
    workerBuilt_.store(false, std::memory_order_relaxed);
    try {
        workerBuilder_ = std::thread([this] {
            try {
                builtWorker_ = makeWorker();
            } catch (...) {
                builtWorker_.reset();  // out of memory: the loop stays single-rate
            }
            workerBuilt_.store(true, std::memory_order_release);
        });
        switchingToMultiRate_ = true;
    } catch (...) {
        // No thread to make it on: stay single-rate.
    }
}

bool HapticLoop::finishMultiRateSwitch() noexcept {
    ++stats_.multiRateSwitchSteps;
    if (!workerBuilt_.load(std::memory_order_acquire)) return false;
    workerBuilder_.join();
    switchingToMultiRate_ = false;
    try {
        if (builtWorker_) {
            // The tissue stood still for every step of the switch, this one too: the physics thread's
            // first steps simulate that time.
            adoptWorker(std::move(builtWorker_), stepIndex_,
                        static_cast<double>(stats_.multiRateSwitchSteps) / config_.rate_hz);
            return true;  // the edits queued meanwhile reach both copies once the physics is held
        }
    } catch (...) {
        worker_.reset();  // out of memory: stay single-rate
    }
    for (int e = 0; e < pendingEditCount_; ++e) applyEdit(pendingEdits_[static_cast<std::size_t>(e)]);
    pendingEditCount_ = 0;
    return false;
}

void HapticLoop::setRealtime(bool on) {
    realtime_ = on;
    // On the wall clock the physics has its own thread; in simulated time it steps with the loop.
    if (worker_) on ? worker_->start() : worker_->stop();
}

physics::Scheme HapticLoop::scheme() const { return worker_ ? worker_->stepper().scheme() : stepper_.scheme(); }

int HapticLoop::substeps() const { return (worker_ ? worker_->stepper() : stepper_).substepsFor(1 / config_.rate_hz); }

double HapticLoop::couplingStiffness_N_per_m(int hand) const {
    const HandState& h = hands_[static_cast<std::size_t>(hand)];
    return std::min(h.setup.couplingStiffness_N_per_m.value_or(config_.couplingStiffness_N_per_m),
                    h.stiffnessCap_N_per_m);
}

std::vector<ServoClock*> HapticLoop::servoClocks() const {
    std::vector<ServoClock*> servos;
    for (const HandState& hand : hands_)
        if (ServoClock* servo = hand.setup.device->servoClock()) servos.push_back(servo);
    return servos;
}

void HapticLoop::zeroAllForces() noexcept {
    for (HandState& hand : hands_) {
        hand.setup.device->commandForce(Vec3::Zero());
        hand.sentForce_N = Vec3::Zero();
    }
}

void HapticLoop::recordLateness(double late_us) noexcept {
    stats_.periodError_us.record(late_us);
    const double period_us = 1e6 / config_.rate_hz;
    const auto missed = static_cast<long>(late_us / period_us);
    if (missed <= 0) return;
    stats_.missedPeriods += missed;
    stats_.overruns += missed;
    if (late_us >= config_.stallPeriods * period_us) {
        ++stats_.stalls;
        stalled_ = true;
    }
}

void HapticLoop::tripWatchdog() noexcept {
    ++stats_.nonFiniteEvents;
    stats_.watchdogTripped = true;
}

bool HapticLoop::letGo(const Frame& frame, std::size_t h) const {
    return hands_[h].setup.touchesOnlyWhileButtonHeld && !(frame[h].sample.buttons & 1u);
}

bool HapticLoop::touching(const Frame& frame, std::size_t h) const {
    const GodObjectProxy& proxy = hands_[h].proxy;
    return frame[h].deviceOk && !letGo(frame, h) && proxy.contact().active &&
           (proxy.position() - frame[h].sample.position_m).squaredNorm() > 1e-18;
}

StepOutput HapticLoop::step() noexcept {
    const auto start = Clock::now();
    stepStart_ = start;
    frameNodes_.clear();
    applyPendingCommands();
    if (std::exchange(stalled_, false)) {
        stallRampStart_s_ = time_s();
        stallToShow_ = true;  // published with this step, so a reader never lags the count by a stall
    }
    StepOutput out;
    out.t_s = time_s();
    out.handCount = handCount();
    Frame frame{};
    readDevices(frame, out);
    moveProxies(frame);
    cut(frame, out);
    coupleTools(frame, out.t_s);
    advanceTissue(frame);
    // The press that decides whether the next step cuts: the force the contact made, before an overrun
    // below withholds it from the device. A late step must not end a cut the hand is still pressing.
    for (std::size_t h = 0; h < hands_.size(); ++h) hands_[h].lastForce_N = frame[h].force_N.norm();
    // Watchdog: a step that overran its period sends no force, rather than a stale one late.
    const double elapsed_us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    if (realtime_ && elapsed_us > 1e6 / config_.rate_hz) {
        ++stats_.overruns;
        for (HandFrame& hand : frame) hand.force_N = Vec3::Zero();
    }
    // After a stall the hand has moved on from where the last force was computed: the force it gets
    // starts again from zero at this step and ramps back in. The tissue and the cut go on as computed.
    if (const double since_s = time_s() - stallRampStart_s_; since_s < config_.stallRampTime_s)
        for (HandFrame& hand : frame) hand.force_N *= std::max(since_s, 0.0) / config_.stallRampTime_s;
    sendForces(frame, out);
    finishStep(out, start, elapsed_us);
    return out;
}

void HapticLoop::readDevices(Frame& frame, StepOutput& out) noexcept {
    // Already in scene metres. A device that reports NaN or infinity (a driver fault, a lost
    // connection) trips the watchdog before its sample can reach a proxy or the tissue.
    for (std::size_t h = 0; h < hands_.size(); ++h) {
        HandFrame& hand = frame[h];
        hand.sample = hands_[h].setup.device->read(out.t_s);
        out.hands[h].device_m = hand.sample.position_m;
        out.hands[h].buttons = hand.sample.buttons;
        out.hands[h].orientation = hand.sample.orientation;
        out.hands[h].oriented = hand.sample.oriented;
        hand.deviceOk = hand.sample.position_m.allFinite() && hand.sample.velocity_m_per_s.allFinite();
        if (!hand.deviceOk) tripWatchdog();
    }
}

void HapticLoop::moveProxies(Frame& frame) noexcept {
    // Each proxy is carried with the surface it touches, then moved toward its device.
    const collision::SurfaceView view = surface();
    for (std::size_t h = 0; h < hands_.size(); ++h) {
        if (!frame[h].deviceOk) continue;
        if (letGo(frame, h))
            hands_[h].proxy.reset(frame[h].sample.position_m);  // free: where the device is, touching nothing
        else
            hands_[h].proxy.update(frame[h].sample.position_m, view, bvh_);
    }
}

void HapticLoop::cut(const Frame& frame, StepOutput& out) noexcept {
    // The scalpel cuts (R14) before this step's forces are spread: a cut may replace the faces they
    // would go to. A cut starts at the contact when the tool presses harder than its threshold (the
    // last step's force): the surface ruptures. It then runs as the blade pays for it (Mahvash &
    // Hayward, cutting/fracture.h): to the crack tip, projected onto the undeformed surface near the
    // cut, so the blade slices through the dimple it presses instead of dragging it along. The crack runs
    // in the rest surface's plane: the dimple's own faces tilt with every step of the press, and a tip
    // kept in their planes wandered millimetres off the blade's line. A device that reports its
    // orientation gives the blade's axis, and the cut is where that line passes through the rest surface;
    // without one the blade is taken as square to the surface (the nearest point). It goes on
    // while the tool presses past the threshold, or while the blade is down in the tissue (under the
    // rest surface near the cut); it ends when the press eases or the blade lifts above the surface.
    // The walls reach as deep as the blade. One cut at a time: it belongs to the hand that started it.
    if (switchingToMultiRate_) return;  // the organ is being copied: the cut goes on once it is
    const auto cutStart = Clock::now();
    bool changed = false;
    for (std::size_t h = 0; h < hands_.size(); ++h) {
        HandState& hand = hands_[h];
        if (letGo(frame, h)) {
            if (cutter_.cutting() && cuttingHand_ == static_cast<int>(h)) {
                cutter_.endCut();  // the hand let go of the blade
                endCrack(hand);
            }
            continue;
        }
        const bool pressing =
            touching(frame, h) && hand.lastForce_N > hand.setup.cutThreshold_N && !stats_.watchdogTripped;
        bool changedHere = false;
        const DeviceSample& sample = frame[h].sample;
        const Vec3 axis = sample.oriented ? cutting::bladeAxis(sample.orientation) : Vec3(Vec3::Zero());
        if (!cutter_.cutting()) {
            // The surface ruptures where the blade goes into it: where its line crosses the surface above
            // the tip, when the device gives the line; else where the proxy holds the tip.
            std::uint32_t face = hand.proxy.contact().face;
            Vec3 bary = hand.proxy.contact().bary;
            if (pressing && !axis.isZero())
                if (const auto hit =
                        bvh_.firstHit(surface(), sample.position_m,
                                      sample.position_m + cutting::ProgressiveCutter::kBladeReach_m * axis);
                    hit && !organ_.isWall(hit->face))
                    face = hit->face, bary = hit->bary;
            if (pressing) changedHere = cutter_.cutAt(face, bary);
            if (cutter_.cutting()) {
                cuttingHand_ = static_cast<int>(h);
                // The surface gave way under the blade: the crack starts where the blade is along the
                // surface, its edge in the tissue, and the pull along the surface builds again as it
                // moves on (the normal part the proxy still holds). A crack started at the proxy, with
                // the blade pressed in at a slant to the rest surface, began stretched sideways by the
                // slant alone, ran off downhill and took that as its way, so a stroke forward never cut
                // again (the bench's stroke on the 100,000 heart: 2 cut events).
                hand.cracking = true;
                hand.bladeAhead = true;
                hand.crackDirection = Vec3::Zero();
                hand.crackNormal = faceNormal(surface(), face);
                hand.crackTip_m = sample.position_m;
                if (const auto blade = cutter_.projectBlade(sample.position_m, axis)) {
                    hand.crackNormal = blade->normal;  // the rest surface's, as the crack runs on
                    hand.crackTip_m = bladeAtSurface(sample.position_m, axis, *blade);
                }
                hand.fractureForce_N = Vec3::Zero();
            }
        } else if (cuttingHand_ == static_cast<int>(h)) {
            const Vec3& device = sample.position_m;
            const auto blade =
                frame[h].deviceOk && !stats_.watchdogTripped ? cutter_.projectBlade(device, axis) : std::nullopt;
            const bool inTissue = blade && blade->depth_m > 0;
            if (blade && (pressing || inTissue)) {
                if (const auto tip = resistBlade(hand, h, sample, bladeAtSurface(device, axis, *blade), blade->normal,
                                                 blade->depth_m))
                    if (const auto at = cutter_.projectBlade(*tip, axis))
                        changedHere = cutter_.cutAt(at->face, at->bary, blade->depth_m);
            } else {
                cutter_.endCut();
                endCrack(hand);
            }
        }
        if (changedHere) afterTopologyChange();  // before the next hand reads the faces
        changed = changed || changedHere;
    }
    if (!cutter_.cutting()) {
        cuttingHand_ = -1;
        for (HandState& hand : hands_) endCrack(hand);  // the cut ended (it ran into a wound or a rim)
    }
    if (changed) {
        out.cut = true;
        ++stats_.cutEvents;
        stats_.cutTime_us.record(std::chrono::duration<double, std::micro>(Clock::now() - cutStart).count());
    }
}

Vec3 HapticLoop::bladeAtSurface(const Vec3& tip_m, const Vec3& axis,
                                const cutting::ProgressiveCutter::BladeProjection& blade) noexcept {
    // Up the blade from its tip by the depth over the cosine of its tilt, to the rest surface's level.
    // A blade flatter than 60 degrees off the normal has no clear place where it goes in: its tip.
    const double cosine = axis.dot(blade.normal);
    return cosine > 0.5 ? Vec3(tip_m + (blade.depth_m / cosine) * axis) : tip_m;
}

std::optional<Vec3> HapticLoop::resistBlade(HandState& hand, std::size_t h, const DeviceSample& blade,
                                            const Vec3& blade_m, const Vec3& normal, double depth_m) noexcept {
    cutting::FractureParams fracture;
    fracture.toughness_J_per_m2 = hand.setup.toughness_J_per_m2.value_or(
        config_.toughness_J_per_m2.value_or(cutting::toughnessFromThreshold(hand.setup.cutThreshold_N)));
    // A tougher or softer region at the crack's tip, where the cut opens next (the rest shape's field read
    // at the deformed tip: the tissue there has moved by the stretch, millimetres).
    fracture.toughness_J_per_m2 *= organ_.scaleAt(hand.crackTip_m).toughness;
    const double k = couplingStiffness_N_per_m(static_cast<int>(h));
    hand.crackNormal = normal;
    // The crack tip is held as a proxy along the surface: the blade ahead of it stretches the tissue
    // (force k x stretch) until that pays for new cut, J x depth; behind it, in its own cut, the blade
    // meets nothing along the surface.
    const Vec3 stretch = blade_m - hand.crackTip_m;
    const Vec3 along = stretch - stretch.dot(normal) * normal;
    // A device that reports its stylus's orientation turns the blade: the crack runs the way its edge
    // faces along the surface, and dragged across that the blade's flat pushes tissue aside uncut.
    // Without one, the blade cuts the way it moves.
    Vec3 edge = Vec3::Zero();
    if (blade.oriented) {
        edge = cutting::bladeEdge(blade.orientation);
        edge -= edge.dot(normal) * normal;
        edge = edge.norm() > 1e-6 ? Vec3(edge.normalized()) : Vec3::Zero();
    }
    std::optional<Vec3> advanced;
    bool ahead = false;
    if (!edge.isZero()) {
        hand.crackDirection = edge;
        ahead = along.dot(edge) > 0;
        if (ahead)
            if (const auto tip =
                    cutting::advancedCrackTipAlongEdge(blade_m, hand.crackTip_m, edge, depth_m, k, fracture))
                hand.crackTip_m = *tip, advanced = tip;
    } else {
        ahead = hand.crackDirection.isZero() || along.dot(hand.crackDirection) > 0;
        if (ahead)
            if (const auto tip = cutting::advancedCrackTip(blade_m, hand.crackTip_m, normal, depth_m, k, fracture)) {
                const Vec3 step = *tip - hand.crackTip_m;
                const Vec3 stepAlong = step - step.dot(normal) * normal;
                if (stepAlong.norm() > 0) hand.crackDirection = stepAlong.normalized();
                hand.crackTip_m = *tip;
                advanced = tip;
            }
    }
    const Vec3 held = blade_m - hand.crackTip_m;
    const Vec3 heldAlong = held - held.dot(normal) * normal;
    hand.fractureForce_N = ahead ? Vec3(-k * heldAlong) : Vec3::Zero();
    hand.bladeAhead = ahead;
    return advanced;
}

void HapticLoop::endCrack(HandState& hand) noexcept {
    hand.cracking = false;
    hand.fractureForce_N = Vec3::Zero();
}

void HapticLoop::coupleTools(Frame& frame, double t_s) noexcept {
    // Each hand's coupling spring from its device to its contact point is a force term of the physics
    // (model_.tools), so the tissue feels it reversed in every integrator stage and stiff contact stays
    // stable. Clamped, ramped in, and kept finite by the watchdog.
    const double ramp = std::clamp((t_s - rampStart_s_) / config_.rampTime_s, 0.0, 1.0);
    // Multi-rate: the surface is the latest physics frame's, which ages until the next one. The touched
    // triangle is carried on at its nodes' velocities for that long, so that the force follows the
    // tissue the hand presses between frames instead of a frozen surface.
    const double ahead =
        worker_ ? std::min(static_cast<double>(stepIndex_ - lastFrameStep_) / config_.rate_hz, config_.maxPhysicsStep_s)
                : 0.0;
    for (std::size_t h = 0; h < static_cast<std::size_t>(kMaxHands); ++h) {
        physics::PointSpring& tool = model_.tools[h];
        const bool wasActive = tool.active;
        tool.active = false;
        if (h >= hands_.size()) continue;
        HandState& hand = hands_[h];
        HandFrame& f = frame[h];
        f.touching = touching(frame, h);
        if (!f.touching && footprintBuilder_ == static_cast<int>(h)) footprintBuilder_ = -1;  // its build is moot
        if (!f.touching && worker_ && wasActive && !stats_.watchdogTripped && f.deviceOk && !letGo(frame, h) &&
            static_cast<double>(stepIndex_ - hand.lastContactStep) < config_.maxPhysicsStep_s * config_.rate_hz) {
            // Multi-rate: contact lost on a surface up to a physics step old. The physics keeps the tool
            // where the device is for that long, pushing only if the tissue reaches it, so that tissue
            // springing back meets the retreating tool as it would in a single-rate loop instead of
            // bouncing free into it. The hand feels nothing until the surface says it touches.
            tool.anchor_m = f.sample.position_m;
            tool.active = true;
            continue;
        }
        if (!f.touching || stats_.watchdogTripped) continue;
        hand.lastContactStep = stepIndex_;
        const double subgrid_m_per_N = loadTissue(h, tool, wasActive);
        stats_.contactNodesMax = std::max(stats_.contactNodesMax, static_cast<long>(tool.count));
        // Anchor so that at this instant the spring reads k (proxy - device): the proxy sits a small
        // offset off the contact point, and the point the spring holds (the footprint's load-weighted
        // mean) a little beneath it.
        tool.anchor_m = f.sample.position_m - (hand.proxy.position() - tool.heldPoint(model_.nodes.position));
        tool.bias_N =
            hand.setup.couplingDamping_Ns_per_m.value_or(config_.couplingDamping_Ns_per_m) * f.sample.velocity_m_per_s;
        // That dent is a spring in series with the coupling: the hand presses through both.
        const double coupling_N_per_m = couplingStiffness_N_per_m(static_cast<int>(h));
        tool.stiffness_N_per_m = coupling_N_per_m / (1 + coupling_N_per_m * subgrid_m_per_N);
        tool.maxForce_N = std::min(hand.setup.device->maxForce_N(), hand.setup.maxForce_N) * maxForceScale_;
        tool.scale = ramp;
        // A probe pushes the way its proxy holds the device out of the tissue (they are apart while it
        // touches), and never pulls against that. The touched face's own normal can point almost anywhere
        // on a rough segmentation, a jittered or folded sliver: taken as the push's way, it zeroed the force
        // of a probe pressed 3-5 mm in for one step in thirteen on a jittered heart, a 1.5 N buzz in the
        // hand. A blade keeps the face's normal: in a wound it is a wall's, made by the cutter, and pushing
        // along the stroke there would drag the lips with the pull the fracture takes (resistBlade); on a
        // rough surface, pushing elsewhere changed where a cut began, and one begun at a turned-over face
        // stalled (the cutter's own defect).
        const bool blade = hand.setup.cutThreshold_N <= tool.maxForce_N;
        const Contact& contact = hand.proxy.contact();
        tool.normal = blade ? Vec3(contact.side * faceNormal(surface(), contact.face))
                            : Vec3((hand.proxy.position() - f.sample.position_m).normalized());
        f.force_N = ahead > 0 ? forceAhead(tool, ahead) : tool.forceOnTool(model_.nodes.position);
        tool.active = true;
        if (!f.force_N.allFinite()) tripWatchdog();
    }
    // A blade that cuts feels, along the surface, the tissue's resistance to fracture instead of the
    // coupling's pull: its proxy, held on the surface or the wound's walls, cannot pass through tissue
    // the blade is about to open. Across the surface the proxy still supports it.
    for (std::size_t h = 0; h < hands_.size(); ++h) {
        HandState& hand = hands_[h];
        if (!hand.cracking || stats_.watchdogTripped) continue;
        const Vec3& n = hand.crackNormal;
        Vec3 force = frame[h].force_N.dot(n) * n + ramp * hand.fractureForce_N;
        const double limit = std::min(hand.setup.device->maxForce_N(), hand.setup.maxForce_N) * maxForceScale_;
        if (force.norm() > limit) force *= limit / force.norm();
        frame[h].force_N = force;
        if (!force.allFinite()) tripWatchdog();
    }
    if (stats_.watchdogTripped)
        for (std::size_t h = 0; h < hands_.size(); ++h) {
            frame[h].force_N = Vec3::Zero();
            model_.tools[h].active = false;
        }
}

double HapticLoop::loadTissue(std::size_t h, physics::PointSpring& tool, bool wasActive) noexcept {
    HandState& hand = hands_[h];
    const Contact& contact = hand.proxy.contact();
    const double radius_m = hand.setup.tipRadius_m;
    if (!(radius_m > 0)) {
        tool.touchTriangle(faces_[contact.face], contact.bary);
        return 0;
    }
    // Built again only once the contact has slid a twentieth of the tip over the tissue (measured on
    // the rest surface, so a press that deforms it does not count), after a new touch, a cut or a new
    // tip. Between, the nodes keep their shares. The hand feels no rebuild: the coupling is anchored
    // afresh every step. A footprint outlives a cut as a load: cuts only add nodes, so its nodes are
    // still the organ's. A scalpel cuts every few steps, and a build restarted at each cut never came
    // to an end on the 1,000,000 heart: the blade pressed on its touched triangle alone and flung
    // nodes metres away.
    const Vec3 at_m = pointOnFace({model_.nodes.restPosition, faces_}, contact.face, contact.bary);
    const bool kept = wasActive && tool.spread && hand.footprintRadius_m == radius_m;
    const int self = static_cast<int>(h);
    if (kept && hand.footprintTopology == topologyVersion_ &&
        (at_m - hand.footprintAt_m).norm() <= kFootprintSlide * radius_m) {
        if (footprintBuilder_ == self) footprintBuilder_ = -1;  // slid back: the footprint it has still fits
        return hand.subgrid_m_per_N;
    }
    const collision::SurfaceView view = surface();
    // A build goes on through a cut, over the faces as they are now; the footprint it makes counts as
    // of the topology it began on, so one more follows it.
    const bool ours = footprintBuilder_ == self && footprintBuildRadius_m_ == radius_m;
    if (footprintBuilder_ < 0 || footprintBuilder_ == self) {  // the builder is free, or ours
        if (!ours) {
            footprint_.begin(view, contact.face, contact.bary, radius_m);
            footprintBuilder_ = self, footprintBuildTopology_ = topologyVersion_, footprintBuildRadius_m_ = radius_m;
            footprintBuildAt_m_ = at_m;
        }
        if (advanceFootprint(view)) {
            const FootprintSpread spread =
                footprint_.finish(view, organ_.vertexFaces(), model_.nodes.anchorStiffness, tool);
            footprintBuilder_ = -1;
            if (!spread.complete) ++stats_.footprintCutSteps;
            hand.subgrid_m_per_N = spread.subgridCompliance_m_per_N;
            hand.footprintAt_m = footprintBuildAt_m_;
            hand.footprintTopology = footprintBuildTopology_;
            hand.footprintRadius_m = radius_m;
            return tool.spread ? hand.subgrid_m_per_N : 0.0;
        }
    }
    // Until its new footprint is whole, the tool loads the one it had, or the touched triangle.
    if (kept) return hand.subgrid_m_per_N;
    tool.touchTriangle(faces_[contact.face], contact.bary);
    return 0;
}

std::size_t footprintFacesPerStep(double ns_per_face) {
    return itemsWithinBudget(ns_per_face, kFootprintBudget_us, kMinFootprintFaces, kFootprintFacesPerStep);
}

bool HapticLoop::advanceFootprint(const collision::SurfaceView& view) noexcept {
    if (!realtime_) return footprint_.advance(view, organ_.vertexFaces(), kFootprintFacesPerStep);
    const std::size_t before = footprint_.facesDone();
    const auto start = Clock::now();
    const bool whole = footprint_.advance(view, organ_.vertexFaces(), footprintFacesPerStep(footprint_ns_per_face_));
    const double ns = std::chrono::duration<double, std::nano>(Clock::now() - start).count();
    if (const std::size_t faces = footprint_.facesDone() - before; faces > 0)
        followCost(footprint_ns_per_face_, ns / static_cast<double>(faces));
    return whole;
}

Vec3 HapticLoop::forceAhead(const physics::PointSpring& tool, double ahead_s) const {
    // The held point is linear in the node positions, so the same weights give its velocity.
    const physics::Nodes& n = model_.nodes;
    return tool.forceAt(tool.heldPoint(n.position) + ahead_s * tool.heldPoint(n.velocity));
}

void HapticLoop::advanceTissue(Frame& frame) noexcept {
    // The tissue moves under the tools' springs; the collision tree and the proxies follow it.
    if (switchingToMultiRate_ && !finishMultiRateSwitch()) return;  // held still while its copy is made
    if (worker_) {
        advanceMultiRate(frame);
        return;
    }
    if (paused_) return;
    const auto physicsStart = Clock::now();
    pressVolume();
    const physics::StepResult result = stepper_.step(model_, 1 / config_.rate_hz);
    const double physics_us = std::chrono::duration<double, std::micro>(Clock::now() - physicsStart).count();
    watchPhysicsTime(physics_us);
    stats_.physicsStepTime_us.record(physics_us);
    lastPhysicsStep_s_ = physics_us / 1e6;
    snapshots_.nodesMoved(stepper_.movedNodes());
    ++stats_.physicsSteps;
    stats_.physicsTime_s += 1 / config_.rate_hz;
    if (stepper_.scheme() == physics::Scheme::BackwardEuler) stats_.solver.record(result.solve);
    lastSolve_ = result.solve;
    if (!result.finite) {
        tripWatchdog();
        for (HandFrame& hand : frame) hand.force_N = Vec3::Zero();
    }
    const collision::SurfaceView view = surface();
    refitMovedFaces();
    for (std::size_t h = 0; h < hands_.size(); ++h)
        if (!letGo(frame, h)) hands_[h].proxy.followSurface(view, bvh_);
}

void HapticLoop::pressVolume() noexcept {
    if (!volumeOn_) return;
    std::span<Vec3> f = model_.nodes.externalForce;
    std::fill(f.begin(), f.end(), Vec3::Zero());
    // A wound left without walls opens the surface: no volume to keep until the model is reset.
    if (!cutter_.woundsClosed()) return;
    physics::addPressureForces(model_.nodes.position, faces_, config_.bulkModulus_Pa, restVolume_m3_, f);
}

void HapticLoop::advanceMultiRate(Frame& frame) noexcept {
    // Cuts and edits reach the physics' copy between its steps: hold it, and bring it up to date once
    // it is idle, with every frame it made taken in first (a part a step, as ever). Until then it steps
    // the organ as it was, with the tools as they were: after a cut they may hold nodes it added, and a
    // step the physics began before it saw the hold read past its copy's arrays with them (once in 63
    // cut events of a scalpel on a 195,000-triangle liver, which flung a node 80 mm).
    bool taken = false;
    if (pendingSync_ || pendingEditCount_ > 0) {
        if (!worker_->idle()) {
            worker_->requestHold();
        } else if (taken = true; takeFrames(frame)) {
            const auto syncStart = Clock::now();
            syncWorker();
            stats_.syncTime_us.record(std::chrono::duration<double, std::micro>(Clock::now() - syncStart).count());
            worker_->release();
        }
    }
    if (!pendingSync_) worker_->setTools(model_.tools);
    if (!worker_->threaded() && !paused_ && (stepIndex_ + 1) % config_.simulatedPhysicsEvery == 0)
        worker_->stepNow(config_.simulatedPhysicsEvery / config_.rate_hz);
    if (!taken || !worker_->threaded()) takeFrames(frame);
}

std::size_t framePartNodes(double intake_ns_per_node, double budget_us) {
    return itemsWithinBudget(intake_ns_per_node, budget_us, kMinFramePartNodes, kFramePartNodes);
}

double HapticLoop::partBudget_us(Clock::time_point now) const noexcept {
    const double spent_us = std::chrono::duration<double, std::micro>(now - stepStart_).count();
    return std::min(kFramePartBudget_us, kStepWorkShare * 1e6 / config_.rate_hz - spent_us);
}

double HapticLoop::partCost_ns_per_node(std::size_t taken, Clock::duration intake) const noexcept {
    // A further part in the same step is sized by what this step's parts cost, when that is more: the
    // running mean lags a frame that moves more than the last ones, and two parts of 2,048 nodes then
    // took 600-900 µs on a 202,120-triangle organ under the scalpel.
    if (taken == 0) return frameIntake_ns_per_node_;
    const double ns = std::chrono::duration<double, std::nano>(intake).count();
    return std::max(frameIntake_ns_per_node_, ns / static_cast<double>(taken));
}

bool HapticLoop::takeFrames(Frame& frame) noexcept {
    // In real time a frame comes in a part at a time, its first nodes (the region grows from the tools,
    // so those are the touched ones) first: a frame of a large region taken whole cost the step that
    // took it 0.7-4.5 ms on the 1,000,000-triangle heart (its tree's refit most), an overrun every
    // frame. A step takes further parts while they move few faces out of their boxes (kFramePartNodes).
    // The nodes not yet in keep the previous frame's state, which shares their faces, so the surface
    // stays closed while it catches up over a few steps; the physics fills its other frame meanwhile and
    // waits for this one back. In simulated time it all comes in at once.
    const bool inParts = realtime_;
    std::size_t taken = 0;
    bool any = false, whole = false;
    movedFaces_.clear();
    Clock::time_point intakeStart;  // read once a frame is there: most steps take none
    auto finish = [&](bool allIn) {
        if (!any) return allIn;
        whole ? refitWholeTree() : bvh_.refitFaces(treeSurface(), movedFaces_);
        const collision::SurfaceView view = surface();
        for (std::size_t h = 0; h < hands_.size(); ++h)
            if (!letGo(frame, h)) hands_[h].proxy.followSurface(view, bvh_);
        if (inParts) {  // what the next parts may cost
            const double ns = std::chrono::duration<double, std::nano>(Clock::now() - intakeStart).count();
            followCost(frameIntake_ns_per_node_, ns / static_cast<double>(std::max<std::size_t>(taken, 1)));
        }
        return allIn;
    };
    physics::Nodes& n = model_.nodes;
    for (;;) {
        const PhysicsFrame* f = worker_->takeFrame();
        if (!f) return finish(true);
        // One clock read a part, in real time only: where the intake began, what it cost, what is left.
        const Clock::time_point now = inParts ? Clock::now() : Clock::time_point{};
        if (inParts && !any) intakeStart = now;
        if (frameCursor_ == 0) {
            lastFrameStep_ = stepIndex_ + 1;  // the frame's state is the next step's present
            if (!f->finite) {
                tripWatchdog();
                for (HandFrame& hand : frame) hand.force_N = Vec3::Zero();
            }
        }
        const std::size_t room =
            inParts ? std::min(framePartNodes(partCost_ns_per_node(taken, now - intakeStart), partBudget_us(now)),
                               kFrameNodesPerStep - taken)
                    : f->nodes.size();
        const std::size_t from = frameCursor_, to = from + std::min(room, f->nodes.size() - from);
        const std::span<const std::uint32_t> part(f->nodes.data() + from, to - from);
        for (std::size_t k = from; k < to; ++k) {
            n.position[f->nodes[k]] = f->positions[k];
            n.velocity[f->nodes[k]] = f->velocities[k];
        }
        snapshots_.nodesMoved(part);
        if (frameNodes_.size() + part.size() <= frameNodes_.capacity())
            frameNodes_.insert(frameNodes_.end(), part.begin(), part.end());
        whole = whole || !gatherFacesRound(part);
        any = true;
        taken += part.size();
        frameCursor_ = to;
        if (to == f->nodes.size()) {
            frameCursor_ = 0;
            if (f->implicit) stats_.solver.record(f->solve);
            lastSolve_ = f->solve;
            ++stats_.physicsSteps;
            stats_.physicsTime_s += f->dt_s;
            stats_.physicsStepTime_us.record(1e6 * f->wall_s);
            lastPhysicsStep_s_ = f->wall_s;
            stats_.physicsTimeLost_s += f->lost_s;
            stats_.toolsOutOfReach = worker_->toolsOutOfReach();
            worker_->releaseFrame();
        }
        if (inParts && (taken == kFrameNodesPerStep || whole || movedFaces_.size() >= kFrameFacesPerStep))
            return finish(frameCursor_ == 0 && worker_->takeFrame() == nullptr);
    }
}

void HapticLoop::syncWorker() noexcept {
    try {
        for (int e = 0; e < pendingEditCount_; ++e) {
            const ModelEdit& edit = pendingEdits_[static_cast<std::size_t>(e)];
            (void)applyModelEdit(model_, edit);
            worker_->edit(edit);
            if (edit.kind == ModelEdit::Kind::ResetModel) {
                snapshots_.allNodesMoved();
                refitWholeTree();  // every node went back to rest
                for (HandState& hand : hands_) hand.proxy.followSurface(surface(), bvh_);
            }
        }
        pendingEditCount_ = 0;
        if (!pendingSync_) return;
        // The cuts since the last sync: the nodes and springs they added or changed, copied over.
        physics::MassSpringModel& w = worker_->model();
        const physics::Nodes& n = model_.nodes;
        const physics::Springs& s = model_.springs;
        const std::size_t oldNodes = w.nodes.size(), oldSprings = w.springs.size();
        auto copyNode = [&](std::uint32_t i) {
            physics::Nodes& wn = w.nodes;
            wn.position[i] = n.position[i], wn.velocity[i] = n.velocity[i], wn.restPosition[i] = n.restPosition[i];
            wn.externalForce[i] = n.externalForce[i], wn.mass[i] = n.mass[i], wn.inverseMass[i] = n.inverseMass[i];
            wn.anchorStiffness[i] = n.anchorStiffness[i], wn.anchorDamping[i] = n.anchorDamping[i];
        };
        auto copySpring = [&](std::uint32_t k) {
            physics::Springs& ws = w.springs;
            ws.a[k] = s.a[k], ws.b[k] = s.b[k], ws.restLength[k] = s.restLength[k];
            ws.stiffness[k] = s.stiffness[k], ws.damping[k] = s.damping[k];
        };
        physics::Nodes& wn = w.nodes;
        for (auto* v : {&wn.position, &wn.velocity, &wn.restPosition, &wn.externalForce}) v->resize(n.size());
        for (auto* v : {&wn.mass, &wn.inverseMass, &wn.anchorStiffness, &wn.anchorDamping}) v->resize(n.size());
        physics::Springs& ws = w.springs;
        ws.a.resize(s.size()), ws.b.resize(s.size());
        for (auto* v : {&ws.restLength, &ws.stiffness, &ws.damping}) v->resize(s.size());
        for (std::uint32_t i : pendingNodes_) copyNode(i);
        for (auto i = static_cast<std::uint32_t>(oldNodes); i < n.size(); ++i) copyNode(i);
        for (std::uint32_t k : pendingSprings_) copySpring(k);
        for (auto k = static_cast<std::uint32_t>(oldSprings); k < s.size(); ++k) copySpring(k);
        worker_->stepper().topologyChanged(w, pendingNodes_, pendingSprings_);
        worker_->modelGrew();
        if (n.size() > frameNodes_.capacity()) reserveTouched(frameNodes_, roomToGrow(n.size()));
    } catch (const std::bad_alloc&) {
        stats_.watchdogTripped = true;  // out of memory following the edit: stop pushing rather than go on
    }
    pendingNodes_.clear();
    pendingSprings_.clear();
    pendingSync_ = false;
}

void HapticLoop::refitMovedFaces() noexcept {
    // Only the faces round the nodes that moved out of their boxes: the rest of the organ sleeps
    // exactly at rest or moves within the margin. A region of more than a quarter of the organ is
    // cheaper to refit whole.
    movedFaces_.clear();
    gatherFacesRound(stepper_.movedNodes()) ? bvh_.refitFaces(treeSurface(), movedFaces_) : refitWholeTree();
}

void HapticLoop::refitWholeTree() noexcept {
    std::copy(model_.nodes.position.begin(), model_.nodes.position.end(), treePositions_.begin());
    bvh_.refit(treeSurface());
}

bool HapticLoop::gatherFacesRound(std::span<const std::uint32_t> nodes) noexcept {
    if (4 * nodes.size() > model_.nodes.size()) return false;
    const double margin_m = bvh_.margin();
    for (std::uint32_t i : nodes) {
        if ((model_.nodes.position[i] - treePositions_[i]).squaredNorm() <= margin_m * margin_m) continue;
        treePositions_[i] = model_.nodes.position[i];
        const std::span<const std::uint32_t> faces = organ_.vertexFaces().of(i);
        if (movedFaces_.size() + faces.size() > movedFaces_.capacity()) return false;  // never allocates
        movedFaces_.insert(movedFaces_.end(), faces.begin(), faces.end());
    }
    return true;
}

void HapticLoop::sendForces(const Frame& frame, StepOutput& out) noexcept {
    // Each device gets its force rate-limited (a jolt can hurt a wrist); `out` records what was sent.
    const double dt = 1 / config_.rate_hz;
    bool limited = false;
    for (std::size_t h = 0; h < hands_.size(); ++h) {
        HandState& hand = hands_[h];
        const Vec3 sent = limitForceRate(hand.sentForce_N, frame[h].force_N, hand.setup.maxForceRate_N_per_s * dt);
        limited = limited || (sent - frame[h].force_N).squaredNorm() > 1e-24;
        hand.setup.device->commandForce(sent);
        hand.sentForce_N = sent;
        HandStep& o = out.hands[h];
        o.force_N = sent;
        o.proxy_m = hand.proxy.position();
        o.contact = frame[h].touching;
        o.cutting = hand.cracking && hand.bladeAhead;
        o.face = hand.proxy.contact().face;
        stats_.maxForce_N = std::max(stats_.maxForce_N, sent.norm());
    }
    stats_.rateLimitedSteps += limited;
}

void HapticLoop::finishStep(StepOutput& out, Clock::time_point start, double elapsed_us) noexcept {
    bool anyContact = false;
    for (std::size_t h = 0; h < hands_.size(); ++h) anyContact = anyContact || out.hands[h].contact;
    out.stepTime_us = elapsed_us;  // what the snapshot published now can say of this step
    stats_.contactSteps += anyContact;
    ++stats_.steps;
    if (stepIndex_ % config_.snapshotEvery == 0 || out.cut || std::exchange(stallToShow_, false)) publishSnapshot(out);
    ++stepIndex_;
    // The step's time includes publishing its snapshot: a slow publication delays the next step as much
    // as slow physics does, and a histogram that left it out missed the 2 ms steps that made a
    // 1,000,000-triangle organ's only overruns.
    out.stepTime_us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    stats_.stepTime_us.record(out.stepTime_us);
    maxStepSinceSnapshot_us_ = std::max(maxStepSinceSnapshot_us_, out.stepTime_us);
}

void HapticLoop::applyPendingCommands() noexcept {
    while (const auto c = commands_.pop()) {
        switch (c->kind) {
            case LoopCommand::Kind::SetCouplingStiffness:
                // Capped at the stiffness the stable step was prepared for; re-preparing would allocate.
                config_.couplingStiffness_N_per_m = std::clamp(c->value, 0.0, preparedCouplingStiffness_);
                break;
            case LoopCommand::Kind::SetCouplingDamping: config_.couplingDamping_Ns_per_m = c->value; break;
            case LoopCommand::Kind::SetMaxForceScale: maxForceScale_ = std::clamp(c->value, 0.0, 1.0); break;
            case LoopCommand::Kind::SetCutThreshold:
                if (c->hand >= 0 && c->hand < handCount())
                    hands_[static_cast<std::size_t>(c->hand)].setup.cutThreshold_N = std::max(c->value, 0.0);
                break;
            case LoopCommand::Kind::SetTipRadius:
                if (c->hand >= 0 && c->hand < handCount() && std::isfinite(c->value))
                    hands_[static_cast<std::size_t>(c->hand)].setup.tipRadius_m = std::clamp(c->value, 0.0, 0.05);
                break;
            case LoopCommand::Kind::ResetModel:
                // The awake nodes find themselves at rest and fall asleep.
                editModel({ModelEdit::Kind::ResetModel, 1});
                break;
            case LoopCommand::Kind::ResetWatchdog:
                // Forces fade in again, as at the start: the hand may have moved while they were off.
                if (stats_.watchdogTripped) rampStart_s_ = time_s();
                stats_.watchdogTripped = false;
                break;
            case LoopCommand::Kind::Pause:
            case LoopCommand::Kind::Resume:
                paused_ = c->kind == LoopCommand::Kind::Pause;
                if (worker_) worker_->setPaused(paused_);
                break;
            case LoopCommand::Kind::ScaleMass: editModel({ModelEdit::Kind::ScaleMass, c->value}); break;
            case LoopCommand::Kind::ScaleStructuralStiffness:
                editModel({ModelEdit::Kind::ScaleStructuralStiffness, c->value});
                break;
            case LoopCommand::Kind::ScaleStructuralDamping:
                editModel({ModelEdit::Kind::ScaleStructuralDamping, c->value});
                break;
            case LoopCommand::Kind::ScalePositioningStiffness:
                editModel({ModelEdit::Kind::ScalePositioningStiffness, c->value});
                break;
            case LoopCommand::Kind::ScalePositioningDamping:
                editModel({ModelEdit::Kind::ScalePositioningDamping, c->value});
                break;
        }
    }
}

void HapticLoop::editModel(const ModelEdit& edit) noexcept {
    if (!worker_ && !switchingToMultiRate_) {
        applyEdit(edit);
    } else if (pendingEditCount_ < static_cast<int>(pendingEdits_.size())) {
        pendingEdits_[static_cast<std::size_t>(pendingEditCount_++)] = edit;  // made once the physics is held
    }
}

void HapticLoop::applyEdit(const ModelEdit& edit) noexcept {
    if (!applyModelEdit(model_, edit)) return;
    if (edit.kind == ModelEdit::Kind::ResetModel) {
        snapshots_.allNodesMoved();
        return;
    }
    try {
        // A stiffer or lighter model needs a smaller step: substeps follow, or Auto turns implicit.
        stepper_.constantsChanged(model_, config_.scheme, 1 / config_.rate_hz);
    } catch (...) {
        stats_.watchdogTripped = true;  // out of memory re-preparing: stop pushing rather than step unprepared
    }
}

void HapticLoop::afterTopologyChange() {
    // Everything here follows only what the cut touched (CutModel::changes), so a cut event costs the
    // same on a 100,000-triangle organ as on the thesis's heart.
    faces_ = organ_.mesh().faces;
    const collision::SurfaceView view = surface();
    const cutting::TopologyChanges& changes = organ_.changes();
    // No refit: the boxes grow to hold the changed and added faces; the step's refit tightens them.
    // The nodes the cut added or moved are where the tree sees them from now on.
    if (model_.nodes.size() > treePositions_.capacity())
        reserveTouched(treePositions_, roomToGrow(model_.nodes.size()));
    treePositions_.resize(model_.nodes.size());
    for (std::uint32_t v : changes.nodes) treePositions_[v] = model_.nodes.position[v];
    bvh_.facesChanged(treeSurface(), changes.faces);
    if (3 * faces_.size() > movedFaces_.capacity()) reserveTouched(movedFaces_, 3 * roomToGrow(faces_.size()));
    footprint_.fitTo(model_.nodes.size(), faces_.size());
    // Multi-rate, the physics' own stepper follows at the sync; this one never steps again (a loop once
    // multi-rate stays so), and bringing it up to date cost 4-6 µs a cut event and up to 0.2 ms at a
    // million triangles.
    if (!worker_) stepper_.topologyChanged(model_, changes.nodes, changes.springs);
    if (volumeOn_) restVolume_m3_ = physics::enclosedVolume(model_.nodes.restPosition, faces_);
    if (worker_) {  // the physics' copy follows once it is held (advanceMultiRate)
        pendingNodes_.insert(pendingNodes_.end(), changes.nodes.begin(), changes.nodes.end());
        pendingSprings_.insert(pendingSprings_.end(), changes.springs.begin(), changes.springs.end());
        pendingSync_ = true;
    }
    // A cut whose opening was left without walls (it ran into an open rim) leaves lips: the surface is
    // no longer closed, so no ray-parity check.
    for (HandState& hand : hands_)
        hand.proxy.surfaceRemeshed(view, bvh_, hand.proxy.params().closedSurface && cutter_.woundsClosed());
    ++topologyVersion_;
    snapshots_.facesChanged(topologyVersion_, changes.faces);
    snapshots_.nodesMoved(changes.nodes);
    organ_.clearChanges();
}

void HapticLoop::publishSnapshot(const StepOutput& out) {
    Snapshot& s =
        snapshots_.fill(model_.nodes.position, faces_, organ_.mesh().uvs, organ_.wallFaces(), topologyVersion_);
    s.hands = out.hands;
    s.handCount = out.handCount;
    s.step = stepIndex_;
    s.stepTime_us = out.stepTime_us;
    s.maxStepTime_us = std::max(maxStepSinceSnapshot_us_, out.stepTime_us);
    maxStepSinceSnapshot_us_ = 0;
    s.stableStep_s = (worker_ ? worker_->stepper() : stepper_).stableStep_s();
    s.substeps = substeps();
    s.scheme = scheme();
    s.solverIterations = lastSolve_.iterations;
    s.solverMultilevel = lastSolve_.multilevel;
    s.multiRate = worker_ != nullptr;
    s.physicsRate_hz = worker_ && time_s() > 0 ? static_cast<double>(stats_.physicsSteps) / time_s() : config_.rate_hz;
    s.physicsRealtimeFactor = time_s() > 0 ? stats_.physicsTime_s / time_s() : 1;
    s.physicsStep_s = lastPhysicsStep_s_;
    s.overruns = stats_.overruns;
    s.stalls = stats_.stalls;
    s.cutEvents = stats_.cutEvents;
    s.cut = cutter_.stats();
    s.contactSteps = stats_.contactSteps;
    s.watchdogTripped = stats_.watchdogTripped;
    s.paused = paused_;
    snapshots_.publish();
}

}  // namespace hapticut::haptics
