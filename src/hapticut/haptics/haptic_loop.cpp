// The haptic loop.
#include "hapticut/haptics/haptic_loop.h"

#include "hapticut/mesh/adjacency.h"

#include <chrono>
#include <cmath>


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
}  // namespace

HapticLoop::HapticLoop(physics::MassSpringModel& model, std::span<const mesh::Face> faces, Device& device, LoopConfig config)
    : model_(model), faces_(faces), device_(device), config_(config), stepper_(config.scheme), proxy_(withClosedFlag(config.proxy, faces)) {
    ownTopology_ = mesh::buildVertexFaces(faces_, model_.nodes.size());
    topology_ = &ownTopology_;
    initialise();
}

HapticLoop::HapticLoop(cutting::CutModel& organ, Device& device, LoopConfig config)
    : model_(organ.model()), faces_(organ.mesh().faces), organ_(&organ), device_(device), config_(config), stepper_(config.scheme),
      proxy_(withClosedFlag(config.proxy, organ.mesh().faces)) {
    topology_ = &organ.vertexFaces();
    cutter_.emplace(organ, config_.cutter);
    initialise();
}

void HapticLoop::initialise() {
    preparedCouplingStiffness_ = config_.couplingStiffness_N_per_m;
    stepper_.setToolStiffness(preparedCouplingStiffness_);
    stepper_.setActiveRegion(config_.activeRegion);
    stepper_.prepare(model_);
    bvh_.build(surface());
    proxy_.setTopology(topology_);
    // Start the proxy where the device is, or just outside the surface if the device begins inside.
    const Vec3 start = device_.read(0).position_m;
    proxy_.reset(start + Vec3(0, 0, 1.0));
    proxy_.update(start, surface(), bvh_);
    for (Snapshot& s : snapshots_.slots()) {
        s.positions.resize(model_.nodes.size());
        s.faces.assign(faces_.begin(), faces_.end());
        if (organ_) s.uvs = organ_->mesh().uvs;
        s.topologyVersion = topologyVersion_;
    }
}

HapticLoop::~HapticLoop() {
    stop();
    device_.commandForce(Vec3::Zero());  // a real device must never be left pushing
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
            case LoopCommand::Kind::SetCutThreshold: config_.cutThreshold_N = std::max(c->value, 0.0); break;
            case LoopCommand::Kind::ResetModel:
                std::copy(model_.nodes.restPosition.begin(), model_.nodes.restPosition.end(), model_.nodes.position.begin());
                std::fill(model_.nodes.velocity.begin(), model_.nodes.velocity.end(), Vec3::Zero());
                break;  // the awake nodes find themselves at rest and fall asleep
            case LoopCommand::Kind::ResetWatchdog: stats_.watchdogTripped = false; break;
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
    const double dt = 1 / config_.rate_hz;

    // 1. Read the device (already in scene metres).
    const DeviceSample dev = device_.read(out.t_s);
    out.device_m = dev.position_m;
    out.buttons = dev.buttons;

    // A device that reports NaN or infinity (a driver fault, a lost connection) trips the watchdog
    // before its sample can reach the proxy or the tissue.
    collision::SurfaceView view = surface();
    const bool deviceOk = dev.position_m.allFinite() && dev.velocity_m_per_s.allFinite();
    if (!deviceOk) {
        ++stats_.nonFiniteEvents;
        stats_.watchdogTripped = true;
    }

    // 2. Move the proxy: carried with the surface it touches, then toward the device.
    if (deviceOk) proxy_.update(dev.position_m, view, bvh_);
    out.proxy_m = proxy_.position();
    const Contact& contact = proxy_.contact();
    auto touching = [&] { return deviceOk && contact.active && (proxy_.position() - dev.position_m).squaredNorm() > 1e-18; };

    // 5. The scalpel cuts (R14). A cut starts at the contact when the tool presses harder than its
    // threshold (the last step's force, so the cut comes before this step's force is spread over faces
    // the cut may replace). It then follows the blade: the device's position projected onto the
    // undeformed surface near the cut, so the blade slices through the dimple it presses instead of
    // dragging it along. It goes on while the tool presses past the threshold, or while the blade is
    // down in its own wound with the proxy fallen in (no contact); it ends when the press eases or the
    // blade lifts above the surface.
    if (cutter_) {
        const auto cutStart = Clock::now();
        bool changed = false;
        const bool pressing = touching() && lastForce_N_ > config_.cutThreshold_N && !stats_.watchdogTripped;
        if (!cutter_->cutting()) {
            if (pressing) changed = cutter_->cutAt(contact.face, contact.bary);
        } else {
            const auto blade = deviceOk && !stats_.watchdogTripped ? cutter_->projectBlade(dev.position_m) : std::nullopt;
            const bool inWound = !touching() && blade && blade->depth_m > 0;
            if (blade && (pressing || inWound)) changed = cutter_->cutAt(blade->face, blade->bary);
            else cutter_->endCut();
        }
        if (changed) {
            afterTopologyChange();
            view = surface();
            out.proxy_m = proxy_.position();
            out.cut = true;
            ++stats_.cutEvents;
            stats_.cutTime_us.record(std::chrono::duration<double, std::micro>(Clock::now() - cutStart).count());
        }
    }
    const bool constrained = touching();

    // 3-4. Force: the coupling spring from the device to the contact point, as a force term of the
    // physics (model_.tool), so the tissue feels it reversed in every integrator stage and stiff contact
    // stays stable. Clamped, ramped in, and kept finite by the watchdog.
    physics::PointSpring& tool = model_.tool;
    tool.active = false;
    Vec3 force = Vec3::Zero();
    if (constrained && !stats_.watchdogTripped) {
        const mesh::Face& face = faces_[contact.face];
        const Vec3 w = contact.bary.cwiseMax(0.0).cwiseAbs2();
        tool.nodes = face;
        tool.bary = contact.bary;
        tool.weights = w.sum() > 0 ? Vec3(w / w.sum()) : Vec3::Constant(1.0 / 3);
        // Anchor so that at this instant the spring reads k (proxy - device): the proxy sits a small
        // offset off the contact point.
        tool.anchor_m = dev.position_m - (proxy_.position() - pointOnFace(view, contact.face, contact.bary));
        tool.bias_N = config_.couplingDamping_Ns_per_m * dev.velocity_m_per_s;
        tool.stiffness_N_per_m = config_.couplingStiffness_N_per_m;
        tool.maxForce_N = device_.maxForce_N() * maxForceScale_;
        tool.scale = std::min(1.0, out.t_s / config_.rampTime_s);
        tool.normal = contact.side * faceNormal(view, contact.face);
        force = tool.forceOnTool(model_.nodes.position);
        tool.active = true;
    }
    if (!force.allFinite()) {
        ++stats_.nonFiniteEvents;
        stats_.watchdogTripped = true;
    }
    if (stats_.watchdogTripped) {
        force = Vec3::Zero();
        tool.active = false;
    }

    // 6. Advance the tissue and refit the collision tree to it.
    if (!paused_) {
        if (!stepper_.step(model_, dt).finite) {
            ++stats_.nonFiniteEvents;
            stats_.watchdogTripped = true;
            force = Vec3::Zero();
        }
        bvh_.refit(view);
        proxy_.followSurface(view, bvh_);
        out.proxy_m = proxy_.position();
    }

    // The press that decides whether the next step cuts: the force the contact made, before an overrun
    // below withholds it from the device. A late step must not end a cut the hand is still pressing.
    lastForce_N_ = force.norm();

    // Watchdog: a step that overran its period sends no force, rather than a stale one late.
    const double elapsed_us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    if (realtime_ && elapsed_us > 1e6 / config_.rate_hz) {
        ++stats_.overruns;
        force = Vec3::Zero();
    }

    // 7. Send the force; publish a snapshot now and then.
    device_.commandForce(force);
    out.force_N = force;
    out.contact = constrained;
    out.face = contact.face;
    out.stepTime_us = elapsed_us;
    stats_.stepTime_us.record(elapsed_us);
    maxStepSinceSnapshot_us_ = std::max(maxStepSinceSnapshot_us_, elapsed_us);
    stats_.maxForce_N = std::max(stats_.maxForce_N, force.norm());
    stats_.contactSteps += constrained;
    ++stats_.steps;
    if (stepIndex_ % config_.snapshotEvery == 0 || out.cut) publishSnapshot(out);
    ++stepIndex_;
    return out;
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
    faces_ = organ_->mesh().faces;
    const collision::SurfaceView view = surface();
    // No refit here: a face split in place becomes part of itself and an opened copy sits where its
    // vertex was, so the old boxes still hold them; the step's own refit after the physics tightens them.
    bvh_.facesAdded(view);  // new faces are searched linearly until a rebuild pays
    stepper_.prepare(model_);  // new nodes and springs, springs moved to the opened copy, the stable step
    // Once a cut has opened, the surface has lips: no longer closed, so no ray-parity check.
    proxy_.surfaceRemeshed(view, bvh_, proxy_.params().closedSurface && !cutter_->stats().opened);
    ++topologyVersion_;
}

void HapticLoop::publishSnapshot(const StepOutput& out) {
    Snapshot& s = snapshots_.writeSlot();
    // Sizes change only after a cut, the one time this may allocate.
    s.positions.assign(model_.nodes.position.begin(), model_.nodes.position.end());
    if (s.topologyVersion != topologyVersion_) {
        s.faces.assign(faces_.begin(), faces_.end());
        if (organ_) s.uvs.assign(organ_->mesh().uvs.begin(), organ_->mesh().uvs.end());
        s.topologyVersion = topologyVersion_;
    }
    s.device_m = out.device_m;
    s.proxy_m = out.proxy_m;
    s.force_N = out.force_N;
    s.contact = out.contact;
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
    device_.commandForce(Vec3::Zero());
}

bool HapticLoop::start(long max_steps, std::function<void(const StepOutput&)> observer) {
    std::string error;
    return start(max_steps, std::move(observer), error);
}

bool HapticLoop::start(long max_steps, std::function<void(const StepOutput&)> observer, std::string& error) {
    stop();
    stopRequested_ = false;
    running_ = true;
    if (ServoClock* servo = device_.servoClock()) {
        // The device's servo thread calls the step at its own rate: no thread of ours, no sleeping.
        realtime_ = true;
        servoSteps_ = 0;
        servoMaxSteps_ = max_steps;
        servoObserver_ = std::move(observer);
        servoBegin_ = servoLast_ = Clock::now();
        const double period_us = 1e6 / servo->servoRate_hz();
        const bool started = servo->startServo(
            [this, period_us] {
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
            },
            error);
        if (!started) {
            running_ = false;
            return false;
        }
        servo_ = servo;
        return true;
    }
    thread_ = std::thread([this, max_steps, observer = std::move(observer)] { threadMain(max_steps, observer); });
    return true;
}

void HapticLoop::stop() {
    stopRequested_ = true;
    if (servo_) {
        servo_->stopServo();
        servo_ = nullptr;
        stats_.wallTime_s += std::chrono::duration<double>(servoLast_ - servoBegin_).count();
        device_.commandForce(Vec3::Zero());
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
    device_.commandForce(Vec3::Zero());
    running_.store(false, std::memory_order_release);
}

}  // namespace hapticut::haptics
