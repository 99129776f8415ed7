// The haptic loop.
#include "hapticut/haptics/haptic_loop.h"

#include "hapticut/common/reserve.h"
#include "hapticut/haptics/force_safety.h"
#include "hapticut/mesh/adjacency.h"

#include <chrono>
#include <cmath>
#include <stdexcept>


namespace hapticut::haptics {

using Clock = std::chrono::steady_clock;

namespace {
/// The proxy may use the ray-parity inside test only on a closed surface (no boundary edges).
ProxyParams withClosedFlag(ProxyParams params, std::span<const mesh::Face> faces) {
    const mesh::MeshAdjacency adj = mesh::buildAdjacency(faces);
    params.closedSurface = true;
    for (std::size_t e = 0; e < adj.edges.size() && params.closedSurface; ++e) params.closedSurface = adj.facesOfEdge(e).size() == 2;
    return params;
}

std::vector<Hand> oneHand(Device& device, const LoopConfig& config) {
    Hand hand;
    hand.device = &device;
    hand.cutThreshold_N = config.cutThreshold_N;
    return {hand};
}
}  // namespace

HapticLoop::HapticLoop(physics::MassSpringModel& model, std::span<const mesh::Face> faces, Device& device, LoopConfig config)
    : model_(model), faces_(faces), config_(config), stepper_(config.scheme) {
    ownTopology_ = mesh::buildVertexFaces(faces_, model_.nodes.size());
    topology_ = &ownTopology_;
    initialise(oneHand(device, config_));
}

HapticLoop::HapticLoop(cutting::CutModel& organ, Device& device, LoopConfig config)
    : HapticLoop(organ, oneHand(device, config), config) {}

HapticLoop::HapticLoop(cutting::CutModel& organ, std::span<const Hand> hands, LoopConfig config)
    : model_(organ.model()), faces_(organ.mesh().faces), organ_(&organ), config_(config), stepper_(config.scheme) {
    topology_ = &organ.vertexFaces();
    cutter_.emplace(organ, config_.cutter);
    initialise(hands);
}

void HapticLoop::initialise(std::span<const Hand> hands) {
    if (hands.empty() || hands.size() > static_cast<std::size_t>(kMaxHands))
        throw std::invalid_argument("a haptic loop takes 1 to " + std::to_string(kMaxHands) + " hands, not " + std::to_string(hands.size()));
    const ProxyParams proxyParams = withClosedFlag(config_.proxy, faces_);
    hands_.reserve(hands.size());
    for (const Hand& h : hands) {
        if (!h.device) throw std::invalid_argument("a hand without a device");
        HandState& state = hands_.emplace_back(HandState{h, GodObjectProxy(proxyParams)});
        state.stiffnessCap_N_per_m = stiffnessCapAt(h.device->maxStiffness_N_per_m(), config_.rate_hz);
    }
    // The stable step allows for every hand pressing the same node at its full coupling.
    preparedCouplingStiffness_ = config_.couplingStiffness_N_per_m;
    stepper_.setToolStiffness(preparedCouplingStiffness_ * static_cast<double>(hands_.size()));
    stepper_.setActiveRegion(config_.activeRegion);
    stepper_.prepare(model_);
    bvh_.build(surface());
    for (HandState& hand : hands_) {
        hand.proxy.setTopology(topology_);
        // Start the proxy where the device is, or just outside the surface if the device begins inside.
        const Vec3 start = hand.setup.device->read(0).position_m;
        hand.proxy.reset(start + Vec3(0, 0, 1.0));
        hand.proxy.update(start, surface(), bvh_);
    }
    // Room for what cuts add, as the organ's own arrays have (CutModel), so publishing rarely allocates.
    for (Snapshot& s : snapshots_.slots()) {
        reserveTouched(s.positions, roomToGrow(model_.nodes.size()));
        s.positions.resize(model_.nodes.size());
        reserveTouched(s.faces, roomToGrow(faces_.size()));
        s.faces.assign(faces_.begin(), faces_.end());
        if (organ_) {
            reserveTouched(s.uvs, roomToGrow(faces_.size()));
            s.uvs.assign(organ_->mesh().uvs.begin(), organ_->mesh().uvs.end());
        }
        s.topologyVersion = topologyVersion_;
        s.handCount = handCount();
    }
    slotVersion_.fill(topologyVersion_);
    faceLog_.reserve(4096);
}

HapticLoop::~HapticLoop() {
    stop();
    zeroAllForces();  // a real device must never be left pushing
}

double HapticLoop::couplingStiffness_N_per_m(int hand) const {
    return std::min(config_.couplingStiffness_N_per_m, hands_[static_cast<std::size_t>(hand)].stiffnessCap_N_per_m);
}

void HapticLoop::zeroAllForces() noexcept {
    for (HandState& hand : hands_) {
        hand.setup.device->commandForce(Vec3::Zero());
        hand.sentForce_N = Vec3::Zero();
    }
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
                if (c->hand >= 0 && c->hand < handCount()) hands_[static_cast<std::size_t>(c->hand)].setup.cutThreshold_N = std::max(c->value, 0.0);
                break;
            case LoopCommand::Kind::ResetModel:
                std::copy(model_.nodes.restPosition.begin(), model_.nodes.restPosition.end(), model_.nodes.position.begin());
                std::fill(model_.nodes.velocity.begin(), model_.nodes.velocity.end(), Vec3::Zero());
                break;  // the awake nodes find themselves at rest and fall asleep
            case LoopCommand::Kind::ResetWatchdog:
                // Forces fade in again, as at the start: the hand may have moved while they were off.
                if (stats_.watchdogTripped) rampStart_s_ = time_s();
                stats_.watchdogTripped = false;
                break;
            case LoopCommand::Kind::Pause: paused_ = true; break;
            case LoopCommand::Kind::Resume: paused_ = false; break;
            case LoopCommand::Kind::ScaleMass:
            case LoopCommand::Kind::ScaleStructuralStiffness:
            case LoopCommand::Kind::ScaleStructuralDamping:
            case LoopCommand::Kind::ScalePositioningStiffness:
            case LoopCommand::Kind::ScalePositioningDamping: scaleMaterial(c->kind, c->value); break;
        }
    }
}

StepOutput HapticLoop::step() noexcept {
    const auto start = Clock::now();
    applyPendingCommands();
    StepOutput out;
    out.t_s = time_s();
    out.handCount = handCount();
    const double dt = 1 / config_.rate_hz;
    const std::size_t handCount = hands_.size();

    // 1. Read the devices (already in scene metres). A device that reports NaN or infinity (a driver
    // fault, a lost connection) trips the watchdog before its sample can reach a proxy or the tissue.
    std::array<DeviceSample, kMaxHands> dev{};
    std::array<bool, kMaxHands> deviceOk{};
    for (std::size_t h = 0; h < handCount; ++h) {
        dev[h] = hands_[h].setup.device->read(out.t_s);
        out.hands[h].device_m = dev[h].position_m;
        out.hands[h].buttons = dev[h].buttons;
        deviceOk[h] = dev[h].position_m.allFinite() && dev[h].velocity_m_per_s.allFinite();
        if (!deviceOk[h]) {
            ++stats_.nonFiniteEvents;
            stats_.watchdogTripped = true;
        }
    }

    // 2. Move each proxy: carried with the surface it touches, then toward its device.
    collision::SurfaceView view = surface();
    for (std::size_t h = 0; h < handCount; ++h)
        if (deviceOk[h]) hands_[h].proxy.update(dev[h].position_m, view, bvh_);
    auto touching = [&](std::size_t h) {
        const GodObjectProxy& proxy = hands_[h].proxy;
        return deviceOk[h] && proxy.contact().active && (proxy.position() - dev[h].position_m).squaredNorm() > 1e-18;
    };

    // 5. The scalpel cuts (R14). A cut starts at the contact when the tool presses harder than its
    // threshold (the last step's force, so the cut comes before this step's force is spread over faces
    // the cut may replace). It then follows the blade: the device's position projected onto the
    // undeformed surface near the cut, so the blade slices through the dimple it presses instead of
    // dragging it along. It goes on while the tool presses past the threshold, or while the blade is
    // down in its own wound with the proxy fallen in (no contact); it ends when the press eases or the
    // blade lifts above the surface. One cut at a time: it belongs to the hand that started it.
    if (cutter_) {
        const auto cutStart = Clock::now();
        bool changed = false;
        for (std::size_t h = 0; h < handCount; ++h) {
            HandState& hand = hands_[h];
            const bool pressing = touching(h) && hand.lastForce_N > hand.setup.cutThreshold_N && !stats_.watchdogTripped;
            bool changedHere = false;
            if (!cutter_->cutting()) {
                if (pressing) changedHere = cutter_->cutAt(hand.proxy.contact().face, hand.proxy.contact().bary);
                if (cutter_->cutting()) cuttingHand_ = static_cast<int>(h);
            } else if (cuttingHand_ == static_cast<int>(h)) {
                const auto blade = deviceOk[h] && !stats_.watchdogTripped ? cutter_->projectBlade(dev[h].position_m) : std::nullopt;
                const bool inWound = !touching(h) && blade && blade->depth_m > 0;
                if (blade && (pressing || inWound)) changedHere = cutter_->cutAt(blade->face, blade->bary);
                else cutter_->endCut();
            }
            if (changedHere) afterTopologyChange();  // before the next hand reads the faces
            changed = changed || changedHere;
        }
        if (!cutter_->cutting()) cuttingHand_ = -1;
        if (changed) {
            view = surface();
            out.cut = true;
            ++stats_.cutEvents;
            stats_.cutTime_us.record(std::chrono::duration<double, std::micro>(Clock::now() - cutStart).count());
        }
    }

    // 3-4. Forces: each hand's coupling spring from its device to its contact point, as a force term
    // of the physics (model_.tools), so the tissue feels it reversed in every integrator stage and
    // stiff contact stays stable. Clamped, ramped in, and kept finite by the watchdog.
    std::array<Vec3, kMaxHands> force{};
    std::array<bool, kMaxHands> constrained{};
    const double ramp = std::clamp((out.t_s - rampStart_s_) / config_.rampTime_s, 0.0, 1.0);
    for (std::size_t h = 0; h < static_cast<std::size_t>(kMaxHands); ++h) {
        physics::PointSpring& tool = model_.tools[h];
        tool.active = false;
        force[h] = Vec3::Zero();
        if (h >= handCount) continue;
        HandState& hand = hands_[h];
        constrained[h] = touching(h);
        if (!constrained[h] || stats_.watchdogTripped) continue;
        const Contact& contact = hand.proxy.contact();
        const mesh::Face& face = faces_[contact.face];
        const Vec3 w = contact.bary.cwiseMax(0.0).cwiseAbs2();
        tool.nodes = face;
        tool.bary = contact.bary;
        tool.weights = w.sum() > 0 ? Vec3(w / w.sum()) : Vec3::Constant(1.0 / 3);
        // Anchor so that at this instant the spring reads k (proxy - device): the proxy sits a small
        // offset off the contact point.
        tool.anchor_m = dev[h].position_m - (hand.proxy.position() - pointOnFace(view, contact.face, contact.bary));
        tool.bias_N = config_.couplingDamping_Ns_per_m * dev[h].velocity_m_per_s;
        tool.stiffness_N_per_m = couplingStiffness_N_per_m(static_cast<int>(h));
        tool.maxForce_N = std::min(hand.setup.device->maxForce_N(), hand.setup.maxForce_N) * maxForceScale_;
        tool.scale = ramp;
        tool.normal = contact.side * faceNormal(view, contact.face);
        force[h] = tool.forceOnTool(model_.nodes.position);
        tool.active = true;
        if (!force[h].allFinite()) {
            ++stats_.nonFiniteEvents;
            stats_.watchdogTripped = true;
        }
    }
    if (stats_.watchdogTripped)
        for (std::size_t h = 0; h < handCount; ++h) {
            force[h] = Vec3::Zero();
            model_.tools[h].active = false;
        }

    // 6. Advance the tissue and refit the collision tree to it.
    if (!paused_) {
        if (!stepper_.step(model_, dt).finite) {
            ++stats_.nonFiniteEvents;
            stats_.watchdogTripped = true;
            force.fill(Vec3::Zero());
        }
        bvh_.refit(view);
        for (std::size_t h = 0; h < handCount; ++h) hands_[h].proxy.followSurface(view, bvh_);
    }

    // The press that decides whether the next step cuts: the force the contact made, before an overrun
    // below withholds it from the device. A late step must not end a cut the hand is still pressing.
    for (std::size_t h = 0; h < handCount; ++h) hands_[h].lastForce_N = force[h].norm();

    // Watchdog: a step that overran its period sends no force, rather than a stale one late.
    const double elapsed_us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    if (realtime_ && elapsed_us > 1e6 / config_.rate_hz) {
        ++stats_.overruns;
        force.fill(Vec3::Zero());
    }

    // 7. Send the forces; publish a snapshot now and then.
    bool anyContact = false;
    for (std::size_t h = 0; h < handCount; ++h) {
        HandStep& o = out.hands[h];
        o.proxy_m = hands_[h].proxy.position();
        o.contact = constrained[h];
        o.face = hands_[h].proxy.contact().face;
        anyContact = anyContact || constrained[h];
    }
    sendForces(force, out);
    out.stepTime_us = elapsed_us;
    stats_.stepTime_us.record(elapsed_us);
    maxStepSinceSnapshot_us_ = std::max(maxStepSinceSnapshot_us_, elapsed_us);
    stats_.contactSteps += anyContact;
    ++stats_.steps;
    if (stepIndex_ % config_.snapshotEvery == 0 || out.cut) publishSnapshot(out);
    ++stepIndex_;
    return out;
}

void HapticLoop::sendForces(const std::array<Vec3, kMaxHands>& force, StepOutput& out) noexcept {
    const double dt = 1 / config_.rate_hz;
    bool limited = false;
    for (std::size_t h = 0; h < hands_.size(); ++h) {
        HandState& hand = hands_[h];
        const Vec3 sent = limitForceRate(hand.sentForce_N, force[h], hand.setup.maxForceRate_N_per_s * dt);
        limited = limited || (sent - force[h]).squaredNorm() > 1e-24;
        hand.setup.device->commandForce(sent);
        hand.sentForce_N = sent;
        out.hands[h].force_N = sent;
        stats_.maxForce_N = std::max(stats_.maxForce_N, sent.norm());
    }
    stats_.rateLimitedSteps += limited;
}

void HapticLoop::scaleMaterial(LoopCommand::Kind kind, double factor) noexcept {
    if (!(factor > 0) || !std::isfinite(factor)) return;
    auto scale = [factor](std::vector<double>& values) {
        for (double& v : values) v *= factor;
    };
    using K = LoopCommand::Kind;
    switch (kind) {
        case K::ScaleMass:
            scale(model_.nodes.mass);
            for (double& m : model_.nodes.inverseMass) m /= factor;
            break;
        case K::ScaleStructuralStiffness: scale(model_.springs.stiffness); break;
        case K::ScaleStructuralDamping: scale(model_.springs.damping); break;
        case K::ScalePositioningStiffness: scale(model_.nodes.anchorStiffness); break;
        case K::ScalePositioningDamping: scale(model_.nodes.anchorDamping); break;
        default: return;
    }
    try {
        stepper_.prepare(model_);  // a stiffer or lighter model needs a smaller step: substeps follow
    } catch (...) {
        stats_.watchdogTripped = true;  // out of memory re-preparing: stop pushing rather than step unprepared
    }
}

void HapticLoop::afterTopologyChange() {
    // Everything here follows only what the cut touched (CutModel::changes), so a cut event costs the
    // same on a 100,000-triangle organ as on the thesis's heart.
    faces_ = organ_->mesh().faces;
    const collision::SurfaceView view = surface();
    const cutting::TopologyChanges& changes = organ_->changes();
    // No refit: the boxes grow to hold the changed and added faces; the step's refit tightens them.
    bvh_.facesChanged(view, changes.faces);
    stepper_.topologyChanged(model_, changes.nodes, changes.springs);
    // Once a cut has opened, the surface has lips: no longer closed, so no ray-parity check.
    for (HandState& hand : hands_) hand.proxy.surfaceRemeshed(view, bvh_, hand.proxy.params().closedSurface && !cutter_->stats().opened);
    ++topologyVersion_;
    for (std::uint32_t f : changes.faces) faceLog_.push_back({topologyVersion_, f});
    organ_->clearChanges();
}

void HapticLoop::publishSnapshot(const StepOutput& out) {
    Snapshot& s = snapshots_.writeSlot();
    // Sizes change only after a cut; the slots were reserved with room to grow.
    s.positions.assign(model_.nodes.position.begin(), model_.nodes.position.end());
    if (s.topologyVersion != topologyVersion_) {
        // Catch up on the faces the cuts since this slot's version changed, not the whole mesh.
        s.faces.resize(faces_.size());
        if (organ_) s.uvs.resize(faces_.size());
        for (const FaceChange& c : faceLog_) {
            if (c.version <= s.topologyVersion) continue;
            s.faces[c.face] = faces_[c.face];
            if (organ_) s.uvs[c.face] = organ_->mesh().uvs[c.face];
        }
        s.topologyVersion = topologyVersion_;
        slotVersion_[static_cast<std::size_t>(&s - snapshots_.slots().data())] = topologyVersion_;
        // What every slot has is needed no more.
        const long everywhere = *std::min_element(slotVersion_.begin(), slotVersion_.end());
        faceLog_.erase(faceLog_.begin(), std::find_if(faceLog_.begin(), faceLog_.end(), [&](const FaceChange& c) { return c.version > everywhere; }));
    }
    s.hands = out.hands;
    s.handCount = out.handCount;
    s.step = stepIndex_;
    s.stepTime_us = out.stepTime_us;
    s.maxStepTime_us = std::max(maxStepSinceSnapshot_us_, out.stepTime_us);
    maxStepSinceSnapshot_us_ = 0;
    s.stableStep_s = stepper_.stableStep_s();
    s.substeps = stepper_.substepsFor(1 / config_.rate_hz);
    s.overruns = stats_.overruns;
    s.cutEvents = stats_.cutEvents;
    s.contactSteps = stats_.contactSteps;
    s.watchdogTripped = stats_.watchdogTripped;
    s.paused = paused_;
    snapshots_.publish();
}

void HapticLoop::runSimulated(long steps, const std::function<void(const StepOutput&)>& observer) {
    realtime_ = false;
    const auto start = Clock::now();
    for (long i = 0; i < steps; ++i) {
        const StepOutput out = step();
        if (observer) observer(out);
    }
    stats_.wallTime_s += std::chrono::duration<double>(Clock::now() - start).count();
    zeroAllForces();
}

bool HapticLoop::start(long max_steps, std::function<void(const StepOutput&)> observer) {
    std::string error;
    return start(max_steps, std::move(observer), error);
}

bool HapticLoop::start(long max_steps, std::function<void(const StepOutput&)> observer, std::string& error) {
    stop();
    stopRequested_ = false;
    running_ = true;
    std::vector<ServoClock*> servos;
    for (HandState& hand : hands_)
        if (ServoClock* servo = hand.setup.device->servoClock()) servos.push_back(servo);
    if (!servos.empty()) {
        // The first device's servo thread calls the step at its own rate: no thread of ours, no sleeping.
        realtime_ = true;
        servoSteps_ = 0;
        servoMaxSteps_ = max_steps;
        servoObserver_ = std::move(observer);
        servoBegin_ = servoLast_ = Clock::now();
        const double period_us = 1e6 / servos.front()->servoRate_hz();
        auto drive = [this, period_us] {
            if (stopRequested_.load(std::memory_order_relaxed) || (servoMaxSteps_ >= 0 && servoSteps_ >= servoMaxSteps_)) {
                running_.store(false, std::memory_order_release);
                return false;
            }
            const auto now = Clock::now();
            if (servoSteps_ > 0) stats_.periodError_us.record(std::max(0.0, std::chrono::duration<double, std::micro>(now - servoLast_).count() - period_us));
            servoLast_ = now;
            const StepOutput out = step();
            if (servoObserver_) servoObserver_(out);
            ++servoSteps_;
            return true;
        };
        // The others only exchange their frames: the state the step reads, the force it wrote.
        auto follow = [this] { return !stopRequested_.load(std::memory_order_relaxed) && running_.load(std::memory_order_relaxed); };
        for (std::size_t i = 0; i < servos.size(); ++i) {
            std::string servoError;
            const bool started = i == 0 ? servos[i]->startServo(drive, servoError) : servos[i]->startServo(follow, servoError);
            if (!started) {
                error = servoError;
                for (std::size_t k = 0; k < i; ++k) servos[k]->stopServo();
                running_ = false;
                zeroAllForces();
                return false;
            }
        }
        servos_ = std::move(servos);
        return true;
    }
    thread_ = std::thread([this, max_steps, observer = std::move(observer)] { threadMain(max_steps, observer); });
    return true;
}

void HapticLoop::stop() {
    stopRequested_ = true;
    if (!servos_.empty()) {
        for (ServoClock* servo : servos_) servo->stopServo();
        servos_.clear();
        stats_.wallTime_s += std::chrono::duration<double>(servoLast_ - servoBegin_).count();
        zeroAllForces();
        running_.store(false, std::memory_order_release);
    }
    if (thread_.joinable()) thread_.join();
}
void HapticLoop::threadMain(long max_steps, std::function<void(const StepOutput&)> observer) {
    realtime_ = true;
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1 / config_.rate_hz));
    // Sleep until shortly before each deadline, then spin: sleeping alone wakes up late, by more than
    // 150 us in 1% of wake-ups on a virtual machine. The spin costs CPU on the haptic thread only.
    const auto spinMargin = std::chrono::microseconds(400);
    const auto begin = Clock::now();
    auto deadline = begin;
    for (long i = 0; (max_steps < 0 || i < max_steps) && !stopRequested_.load(std::memory_order_relaxed); ++i) {
        if (deadline - Clock::now() > spinMargin) std::this_thread::sleep_until(deadline - spinMargin);
        while (Clock::now() < deadline) {
        }
        stats_.periodError_us.record(std::chrono::duration<double, std::micro>(Clock::now() - deadline).count());
        const StepOutput out = step();
        if (observer) observer(out);
        deadline += period;
        // After a long stall, drop the missed deadlines instead of racing to catch up.
        if (Clock::now() - deadline > 10 * period) deadline = Clock::now();
    }
    stats_.wallTime_s += std::chrono::duration<double>(Clock::now() - begin).count();
    zeroAllForces();
    running_.store(false, std::memory_order_release);
}

}  // namespace hapticut::haptics
