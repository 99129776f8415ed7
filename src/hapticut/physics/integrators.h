// Explicit time integrators behind one interface (SPEC R5), with automatic substepping for stability.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "hapticut/physics/mass_spring_model.h"

namespace hapticut::physics {

enum class Scheme { ExplicitEuler, Midpoint, RungeKutta4, SymplecticEuler };

std::string_view schemeName(Scheme scheme);  // "euler", "midpoint", "rk4", "symplectic"
std::optional<Scheme> parseScheme(std::string_view name);

struct StepResult {
    int substeps = 1;
    bool finite = true;  // false: the step produced NaN/inf; the state was rolled back and velocities zeroed
};

/// Largest time step (s) for which every node's local modes are stable under `scheme`: for each node,
/// its own positioning mode and its highest mode against its neighbours (2·Σk/m, as in a chain),
/// each with its damping, must have an amplification of at most 1. A 0.9 safety factor is applied.
/// `extra_stiffness_N_per_m` is added to every node, for a tool spring that may attach anywhere.
double stableTimeStep(const MassSpringModel& model, Scheme scheme, double extra_stiffness_N_per_m = 0);

/// Advances a model in time. Owns scratch buffers so that stepping never allocates once prepared.
class Stepper {
public:
    explicit Stepper(Scheme scheme = Scheme::RungeKutta4) : scheme_(scheme) {}

    Scheme scheme() const { return scheme_; }
    void setScheme(Scheme scheme);
    /// Sizes buffers and estimates the stable step for this model; call after any change to the
    /// model's size or constants. Stepping an unprepared or resized model prepares it first.
    void prepare(const MassSpringModel& model);
    /// After a topology edit (a cut): brings buffers, the springs of each node and the stable step up to
    /// date for the listed nodes and springs (new ones, or ones whose mass, anchor, ends or stiffness
    /// changed; repeats allowed), in time proportional to them, not to the model. The stable step only
    /// ever shrinks here: a cut splits masses and shortens springs, and a bound kept from before the
    /// edit stays safe. Wakes the listed nodes. Allocates only when the model outgrows its reserve.
    void topologyChanged(const MassSpringModel& model, std::span<const std::uint32_t> nodes, std::span<const std::uint32_t> springs);
    /// Stiffness a tool may add to any node (the haptic coupling); counted in the stable step.
    void setToolStiffness(double stiffness_N_per_m);
    /// Substeps are off when false: every step is taken as asked, stable or not.
    void setAutoSubstep(bool on) { autoSubstep_ = on; }
    double stableStep_s() const { return stableDt_; }
    int substepsFor(double dt_s) const;

    /// Active region (local simulation, after Mosegaard): only nodes that move are integrated. A node
    /// sleeps once the thesis's snap rule holds it at rest and the force on it is negligible; it wakes
    /// when a spring pulls on it, when the tool touches it, or by wake(). Sleeping nodes sit exactly at
    /// rest, so the forces between them are exactly zero and leaving them out changes nothing.
    /// External forces on a sleeping node need a wake() call.
    void setActiveRegion(bool on);
    void wake(std::uint32_t node);
    std::size_t awakeCount() const { return activeRegion_ ? activeNodes_.size() : preparedNodes_; }

    /// Advances by dt_s, in as many equal substeps as stability needs; applies the snap-back rule.
    StepResult step(MassSpringModel& model, double dt_s);

private:
    void substep(MassSpringModel& model, double h);
    void accelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v);
    void rebuildActiveLists(const MassSpringModel& model);
    void updateSleep(const MassSpringModel& model);
    /// Lowers rawStableDt_ to what node i's own modes allow.
    void lowerStableStepAt(const MassSpringModel& model, std::uint32_t i);
    /// Capacity for `n` nodes and `ns` springs, with room to grow, so that cuts rarely reallocate.
    void reserveFor(std::size_t n, std::size_t ns);

    Scheme scheme_;
    bool autoSubstep_ = true;
    double stableDt_ = 0, rawStableDt_ = 0;  // with and without the safety factor
    double toolStiffness_ = 0;
    std::size_t preparedNodes_ = static_cast<std::size_t>(-1), preparedSprings_ = 0;
    std::vector<Vec3> x0_, v0_, xs_, vs_, a_, dx_, dv_;

    // The nodes the integrator loops over: all of them, or the awake ones.
    std::vector<std::uint32_t> allNodes_;
    bool activeRegion_ = false, activeDirty_ = true;
    std::vector<std::uint8_t> awake_, touchedMark_, springMark_, wakeNext_;
    std::vector<std::uint32_t> activeNodes_, touchedNodes_, activeSprings_, wakeList_;
    std::vector<std::vector<std::uint32_t>> nodeSprings_;       // the springs at each node
    std::vector<std::array<std::uint32_t, 2>> springEnds_;      // each spring's ends as last seen
};

}  // namespace hapticut::physics
