// The multi-rate loop's physics thread, and the frames and edits it exchanges with the haptic thread.
#include "hapticut/haptics/physics_worker.h"

#include <algorithm>
#include <cmath>

#include "hapticut/common/reserve.h"

namespace hapticut::haptics {

bool applyModelEdit(physics::MassSpringModel& model, const ModelEdit& edit) {
    if (edit.kind != ModelEdit::Kind::ResetModel && !(edit.factor > 0 && std::isfinite(edit.factor))) return false;
    physics::Nodes& n = model.nodes;
    auto scale = [&](std::vector<double>& values) {
        for (double& v : values) v *= edit.factor;
    };
    using K = ModelEdit::Kind;
    switch (edit.kind) {
        case K::ResetModel:
            std::copy(n.restPosition.begin(), n.restPosition.end(), n.position.begin());
            std::fill(n.velocity.begin(), n.velocity.end(), Vec3::Zero());
            break;
        case K::ScaleMass:
            scale(n.mass);
            for (double& m : n.inverseMass) m /= edit.factor;
            break;
        case K::ScaleStructuralStiffness: scale(model.springs.stiffness); break;
        case K::ScaleStructuralDamping: scale(model.springs.damping); break;
        case K::ScalePositioningStiffness: scale(n.anchorStiffness); break;
        case K::ScalePositioningDamping: scale(n.anchorDamping); break;
    }
    return true;
}

PhysicsWorker::PhysicsWorker(const physics::MassSpringModel& model, const physics::Stepper& stepper,
                             physics::Scheme requested, double period_s, double maxStep_s)
    // Not the tools' contacts: the loop writes them every step, also while a copy is made on another
    // thread (HapticLoop::beginMultiRateSwitch), and hands them over before each step (setTools).
    : model_{model.nodes, model.springs, model.gravity_m_per_s2, {}, model.snapDistance_m, model.snapSpeed_m_per_s},
      stepper_(stepper),
      requested_(requested),
      period_s_(period_s),
      maxStep_s_(std::max(maxStep_s, period_s)) {
    // A copied vector has no room to spare: give the copy the organ's room to grow, so that the cuts
    // copied into it (HapticLoop::syncWorker) rarely reallocate a whole array.
    physics::Nodes& n = model_.nodes;
    const std::size_t nodes = roomToGrow(n.size()), springs = roomToGrow(model_.springs.size());
    for (auto* v : {&n.position, &n.velocity, &n.restPosition, &n.externalForce}) reserveTouched(*v, nodes);
    for (auto* v : {&n.mass, &n.inverseMass, &n.anchorStiffness, &n.anchorDamping}) reserveTouched(*v, nodes);
    reserveTouched(model_.springs.a, springs);
    reserveTouched(model_.springs.b, springs);
    for (auto* v : {&model_.springs.restLength, &model_.springs.stiffness, &model_.springs.damping})
        reserveTouched(*v, springs);
    stepper_.prepare(model_);
    modelGrew();
}

void PhysicsWorker::modelGrew() {
    // A frame holds at most every node. Only once cuts outgrow that does it take room to grow again:
    // asking for room to grow at every cut moved and rewrote every frame each time, 3 ms a cut and up to
    // 180 ms at the first on a 1,000,000-triangle organ.
    const std::size_t nodes = model_.nodes.size(), room = roomToGrow(nodes);
    for (PhysicsFrame& f : frames_) {
        if (f.nodes.capacity() < nodes) reserveTouched(f.nodes, room);
        if (f.positions.capacity() < nodes) reserveTouched(f.positions, room);
        if (f.velocities.capacity() < nodes) reserveTouched(f.velocities, room);
    }
}

void PhysicsWorker::edit(const ModelEdit& edit) {
    if (applyModelEdit(model_, edit) && edit.kind != ModelEdit::Kind::ResetModel)
        stepper_.constantsChanged(model_, requested_, period_s_);
}

void PhysicsWorker::start(double behind_s) {
    if (threaded()) return;
    // On its own thread the physics keeps pace with the wall clock: a step's Newton iterations stop once
    // another would take it past the time it simulates.
    stepper_.keepPace(1.0);
    stop_ = false;
    thread_ = std::thread([this, behind_s] { threadMain(behind_s); });
}

void PhysicsWorker::stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
}

void PhysicsWorker::setTools(const Tools& tools) {
    // Only the loaded nodes' part of each tool: its arrays are sized for the largest footprint.
    Tools& slot = tools_.writeSlot();
    for (std::size_t t = 0; t < tools.size(); ++t) tools[t].copyTo(slot[t]);
    tools_.publish();
}

const PhysicsFrame* PhysicsWorker::takeFrame() {
    if (!ready_[static_cast<std::size_t>(readFrame_)].load(std::memory_order_acquire)) return nullptr;
    return &frames_[static_cast<std::size_t>(readFrame_)];
}

void PhysicsWorker::releaseFrame() {
    ready_[static_cast<std::size_t>(readFrame_)].store(false, std::memory_order_release);
    readFrame_ ^= 1;
}

void PhysicsWorker::stepOnce(double dt_s, double lost_s, double owed_s) {
    const Tools& tools = tools_.readLatest();
    for (std::size_t t = 0; t < tools.size(); ++t) {
        tools[t].copyTo(model_.tools[t]);
        // A tool on nodes a cut added that this copy has not been given yet would read and push past its
        // arrays: it waits for the sync (HapticLoop::advanceMultiRate publishes none meanwhile).
        physics::PointSpring& tool = model_.tools[t];
        const std::span<const std::uint32_t> loaded = tool.loadedNodes();
        const std::size_t nodes = model_.nodes.size();
        if (tool.active && std::any_of(loaded.begin(), loaded.end(), [&](std::uint32_t i) { return i >= nodes; })) {
            tool.active = false;
            toolsOutOfReach_.fetch_add(1, std::memory_order_relaxed);
        }
    }
    const auto start = std::chrono::steady_clock::now();
    const physics::StepResult result = stepper_.step(model_, dt_s);
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // The frame the haptic side gave back; in simulated time it was given back before this call.
    PhysicsFrame& frame = frames_[static_cast<std::size_t>(writeFrame_)];
    const std::span<const std::uint32_t> moved = stepper_.movedNodes();
    frame.nodes.assign(moved.begin(), moved.end());
    frame.positions.resize(moved.size());
    frame.velocities.resize(moved.size());
    for (std::size_t k = 0; k < moved.size(); ++k) {
        frame.positions[k] = model_.nodes.position[moved[k]];
        frame.velocities[k] = model_.nodes.velocity[moved[k]];
    }
    frame.dt_s = dt_s;
    frame.wall_s = wall_s;
    frame.lost_s = lost_s;
    frame.owed_s = owed_s;
    frame.finite = result.finite;
    frame.solve = result.solve;
    frame.implicit = stepper_.scheme() == physics::Scheme::BackwardEuler;
    ready_[static_cast<std::size_t>(writeFrame_)].store(true, std::memory_order_release);
    writeFrame_ ^= 1;
    steps_.fetch_add(1, std::memory_order_relaxed);
    simulated_s_.store(simulated_s_.load(std::memory_order_relaxed) + dt_s, std::memory_order_relaxed);
}

void PhysicsWorker::stepNow(double dt_s) {
    if (ready_[static_cast<std::size_t>(writeFrame_)].load(std::memory_order_acquire)) return;  // not taken yet
    stepOnce(dt_s);
}

void PhysicsWorker::threadMain(double behind_s) {
    using Clock = std::chrono::steady_clock;
    auto pause = [] { std::this_thread::sleep_for(std::chrono::microseconds(50)); };
    auto last = Clock::now();
    // Time the tissue stood still before this thread began, owed to the steps to come: the switch to
    // multi-rate held it for 89 ms on a rough 60,000-face organ, and the tissue was that far behind the
    // wall clock to the end of the run.
    double owed_s = std::max(0.0, behind_s);
    // Wall time a step could not simulate, up to the longest step (or the time held before the thread
    // began, if more), is carried into the steps after it. Under a scalpel on the 1,000,000-triangle
    // heart the steps settle at 40-60 ms, and a cut's hold adds the step in progress: dropped, that time
    // came to 0.03-0.06 s of a 2.8 s stroke, and the tissue stayed that far behind the wall clock.
    // Further behind than that the physics cannot keep up, and loses the rest.
    const double carried_max_s = std::max(maxStep_s_, owed_s);
    while (!stop_.load(std::memory_order_relaxed)) {
        const bool frameFree = !ready_[static_cast<std::size_t>(writeFrame_)].load(std::memory_order_acquire);
        if (hold_.load(std::memory_order_acquire) && frameFree) {
            // Every frame made so far is out, and the haptic side takes them in before it edits both copies.
            idle_.store(true, std::memory_order_release);
            while (hold_.load(std::memory_order_acquire) && !stop_.load(std::memory_order_relaxed)) pause();
            idle_.store(false, std::memory_order_release);
            // The held time is simulated by the next step: a cut's hold lasts the step in progress and a
            // haptic period or two, and a step started after it at `now` lost all of that, 0.3 s of
            // every second while a scalpel cut a 100,000-triangle organ.
            continue;
        }
        if (!frameFree || paused_.load(std::memory_order_relaxed)) {
            pause();
            if (paused_.load(std::memory_order_relaxed)) last = Clock::now();
            continue;
        }
        // As long as the previous step took, so that the tissue keeps up with the wall clock; within a
        // haptic period and maxStep (beyond it the physics falls behind, and the report says so).
        const auto now = Clock::now();
        const double elapsed = std::chrono::duration<double>(now - last).count();
        if (elapsed + owed_s < period_s_) {
            pause();
            continue;
        }
        const double due_s = elapsed + owed_s;
        const double dt = std::min(due_s, maxStep_s_);
        owed_s = std::min(due_s - dt, carried_max_s);
        last = now;
        stepOnce(dt, due_s - dt - owed_s, owed_s);
    }
    idle_.store(true, std::memory_order_release);
}

}  // namespace hapticut::haptics
