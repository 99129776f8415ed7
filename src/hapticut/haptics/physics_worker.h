// The physics of a multi-rate loop (after Knott & Kuhlen's multi-rate single-point contact): the tissue
// stepped on its own thread at the rate it can hold, with a step as long as the last one took, while
// the haptic thread keeps its period against the latest surface. The worker steps its own copy of the
// model; each step's moved nodes reach the haptic side's copy in order, through two frames handed back
// and forth. Nothing here locks, and nothing allocates once started.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <span>
#include <thread>
#include <vector>

#include "hapticut/common/triple_buffer.h"
#include "hapticut/physics/integrators.h"

namespace hapticut::haptics {

/// What one physics step changed: the nodes it moved, with their new state.
struct PhysicsFrame {
    std::vector<std::uint32_t> nodes;
    std::vector<Vec3> positions, velocities;
    double dt_s = 0;
    double wall_s = 0;  // how long the step took to compute
    // Wall time this step left unsimulated: more had passed than the longest step allowed, and than the
    // steps after it may carry (PhysicsWorker::start).
    double lost_s = 0;
    double owed_s = 0;  // wall time this step left for the steps after it to simulate
    bool finite = true;
    physics::SolveReport solve;
    bool implicit = false;  // solve is the implicit scheme's
};

/// A change to the model the user asks for; in a multi-rate loop both copies go through here while the
/// worker is held, so they stay the same.
struct ModelEdit {
    enum class Kind {
        ResetModel,
        ScaleMass,
        ScaleStructuralStiffness,
        ScaleStructuralDamping,
        ScalePositioningStiffness,
        ScalePositioningDamping
    } kind = Kind::ResetModel;
    double factor = 1;
};

/// Applies an edit to a model. False for a scale that is not a positive finite number (nothing changes).
bool applyModelEdit(physics::MassSpringModel& model, const ModelEdit& edit);

class PhysicsWorker {
public:
    using Tools = std::array<physics::PointSpring, physics::kMaxTools>;

    /// A copy of `model`, stepped with `stepper`'s settings (scheme, tool stiffness, solver, region);
    /// `requested` is the scheme asked for (Auto is decided again after an edit).
    PhysicsWorker(const physics::MassSpringModel& model, const physics::Stepper& stepper, physics::Scheme requested,
                  double period_s, double maxStep_s);
    ~PhysicsWorker() { stop(); }
    PhysicsWorker(const PhysicsWorker&) = delete;
    PhysicsWorker& operator=(const PhysicsWorker&) = delete;

    /// Starts stepping on its own thread, each step as long as the previous one took on the wall clock
    /// (at least one haptic period, at most maxStep_s). What a step cannot simulate within maxStep_s, up
    /// to another maxStep_s, the steps after it do: the tissue catches up with the wall clock after a
    /// long hold; more than that is lost, and the frame says so. `behind_s` is wall time the tissue was
    /// held still before (Auto's switch to multi-rate, while this copy was made): the first steps
    /// simulate it too, each within maxStep_s.
    void start(double behind_s = 0);
    void stop();
    bool threaded() const { return thread_.joinable(); }
    /// Without the thread (simulated time): one step of dt_s, now, on the calling thread. Waits for the
    /// haptic side to take the previous frame first: call takeFrame after each.
    void stepNow(double dt_s);

    // From the haptic thread.
    /// The tools as the haptic side set them this period; the next step uses the latest.
    void setTools(const Tools& tools);
    /// The next frame in order, or nullptr; hand it back with releaseFrame before taking another.
    const PhysicsFrame* takeFrame();
    void releaseFrame();
    /// Makes `edit` to the worker's copy: only while idle(). A material change prepares the stepper
    /// again, which allocates, like the single-rate loop's: a user's action, not a steady state.
    void edit(const ModelEdit& edit);
    /// After a topology edit made to the worker's copy (while idle()): room for what it grew by.
    void modelGrew();
    void setPaused(bool paused) { paused_.store(paused, std::memory_order_relaxed); }
    /// Asks the thread to stop between steps. idle() says when it has (every frame it made is out).
    void requestHold() { hold_.store(true, std::memory_order_release); }
    bool idle() const { return !threaded() || idle_.load(std::memory_order_acquire); }
    void release() { hold_.store(false, std::memory_order_release); }

    /// The worker's copy and stepper: only while idle() (or not threaded), for a topology edit.
    physics::MassSpringModel& model() { return model_; }
    physics::Stepper& stepper() { return stepper_; }

    // Counts, safe from any thread.
    long steps() const { return steps_.load(std::memory_order_relaxed); }
    double simulatedTime_s() const { return simulated_s_.load(std::memory_order_relaxed); }
    /// Tools left out of a step because they named a node this copy did not have yet.
    long toolsOutOfReach() const { return toolsOutOfReach_.load(std::memory_order_relaxed); }

private:
    void threadMain(double behind_s);
    /// Steps once by dt_s and fills the free frame with what moved; `lost_s` of wall time went unsimulated,
    /// and `owed_s` is left to the next steps.
    void stepOnce(double dt_s, double lost_s = 0, double owed_s = 0);

    physics::MassSpringModel model_;
    physics::Stepper stepper_;
    physics::Scheme requested_;
    double period_s_, maxStep_s_;
    TripleBuffer<Tools> tools_;
    // Two frames handed back and forth: the worker fills the one the haptic side gave back.
    std::array<PhysicsFrame, 2> frames_;
    std::array<std::atomic<bool>, 2> ready_{};  // filled and not yet given back
    int writeFrame_ = 0, readFrame_ = 0;
    std::thread thread_;
    std::atomic<bool> stop_{false}, hold_{false}, idle_{false}, paused_{false};
    std::atomic<long> steps_{0}, toolsOutOfReach_{0};
    std::atomic<double> simulated_s_{0};
};

}  // namespace hapticut::haptics
