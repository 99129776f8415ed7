// The time integrators behind one interface (SPEC R5): a Stepper substeps the explicit schemes for
// stability (stability.h), solves the implicit one (backward_euler.h) in one step, and integrates only
// the active region (active_region.h); each explicit scheme is one substep function.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/physics/active_region.h"
#include "hapticut/physics/backward_euler.h"
#include "hapticut/physics/mass_spring_model.h"
#include "hapticut/physics/node_springs.h"
#include "hapticut/physics/scheme.h"
#include "hapticut/physics/spring_forces.h"
#include "hapticut/physics/stability.h"

namespace hapticut::physics {

struct StepResult {
    int substeps = 1;
    bool finite = true;  // false: the step produced NaN/inf; the state was rolled back and velocities zeroed
    SolveReport solve;   // the implicit scheme's linear solve; zero iterations for the explicit ones
};

/// Advances a model in time. Owns scratch buffers so that stepping never allocates once prepared.
class Stepper {
public:
    /// Scheme::Auto is resolved (resolveScheme) on the first step, when the step size is known.
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
    void topologyChanged(const MassSpringModel& model, std::span<const std::uint32_t> nodes,
                         std::span<const std::uint32_t> springs);
    /// After the model's constants changed (a material edit): decides `requested` again for steps of
    /// dt_s (Auto may turn implicit) and prepares. Allocates, like prepare().
    void constantsChanged(const MassSpringModel& model, Scheme requested, double dt_s);
    /// Stiffness a tool may add to any node (the haptic coupling); counted in the stable step.
    void setToolStiffness(double stiffness_N_per_m);
    double toolStiffness_N_per_m() const { return toolStiffness_; }
    /// When the implicit scheme's linear solve stops.
    void setSolverSettings(SolverSettings settings) { implicit_.setSettings(settings); }
    /// The implicit scheme's Newton iterations on the wall clock (BackwardEuler::keepPace).
    void keepPace(double share) { implicit_.keepPace(share); }
    const SolverSettings& solverSettings() const { return implicit_.settings(); }
    /// Provot's strain limit (strain_limit.h) after every step: springs stretched more than this share
    /// of their rest length are pulled back to it; 0: off.
    void setStrainLimit(double maxStrain) { strainLimit_ = maxStrain; }
    double strainLimit() const { return strainLimit_; }
    /// Substeps are off when false: every step is taken as asked, stable or not.
    void setAutoSubstep(bool on) { autoSubstep_ = on; }
    double stableStep_s() const { return stableDt_; }
    int substepsFor(double dt_s) const;

    /// Integrates only the active region (ActiveRegion) when on. External forces on a sleeping node
    /// need a wake() call.
    void setActiveRegion(bool on);
    void wake(std::uint32_t node) { region_.wake(node); }
    std::size_t awakeCount() const { return activeRegion_ ? region_.nodes().size() : preparedNodes_; }
    /// The nodes the last step integrated: every node that can have moved in it.
    std::span<const std::uint32_t> movedNodes() const {
        return activeRegion_ ? std::span<const std::uint32_t>(moved_) : std::span<const std::uint32_t>(allNodes_);
    }

    /// Advances by dt_s, in as many equal substeps as stability needs; applies the snap-back rule.
    StepResult step(MassSpringModel& model, double dt_s);

private:
    void substep(MassSpringModel& model, double h);
    // One substep of h seconds of each scheme, over the nodes being integrated.
    void explicitEulerSubstep(MassSpringModel& model, double h);
    void symplecticEulerSubstep(MassSpringModel& model, double h);
    void midpointSubstep(MassSpringModel& model, double h);
    void rungeKutta4Substep(MassSpringModel& model, double h);
    /// All nodes, or the awake ones.
    std::span<const std::uint32_t> integratedNodes() const;
    void accelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v);
    /// After an active region's step: the forces at the end state into a_, for the nodes whose sleep or
    /// snapping they decide (updateSleep).
    void endStateForces(const MassSpringModel& model);
    /// Lowers rawStableDt_ to what node i's own modes allow.
    void lowerStableStepAt(const MassSpringModel& model, std::uint32_t i);
    /// Capacity for `n` nodes and `ns` springs, with room to grow, so that cuts rarely reallocate.
    void reserveFor(std::size_t n, std::size_t ns);
    /// The region the implicit solve covers: the awake nodes, or all of them.
    SolveRegion solveRegion() const;

    Scheme scheme_;
    bool autoSubstep_ = true;
    double stableDt_ = 0, rawStableDt_ = 0;  // with and without the safety factor
    double toolStiffness_ = 0;
    double strainLimit_ = 0;
    std::size_t preparedNodes_ = static_cast<std::size_t>(-1), preparedSprings_ = 0;
    std::vector<Vec3> x0_, xs_, vs_, a_, dx_, dv_;
    ForceRows forces_;  // where the explicit schemes sum a stage's forces
    std::vector<std::uint32_t> allNodes_, allSprings_;
    std::vector<std::uint32_t> moved_;      // the active region's nodes in the last step
    std::vector<std::uint32_t> snapped_;    // the nodes the snap rule put back at rest in the last step
    std::vector<std::uint32_t> atRest_;     // the region's touched nodes at rest after a step (endStateForces)
    std::vector<std::uint32_t> visitedIn_;  // per node: the topologyChanged call that last visited it
    std::uint32_t visit_ = 0;
    BackwardEuler implicit_;
    bool activeRegion_ = false;
    ActiveRegion region_;
    // Changes whenever the solve region's lists or the springs' ends may have: at every preparation,
    // edit and switch of the active region, and when the region's lists change (SolveRegion::layout).
    std::uint64_t layout_ = 1, regionVersion_ = 0;
    NodeSprings springsAt_;
};

}  // namespace hapticut::physics
