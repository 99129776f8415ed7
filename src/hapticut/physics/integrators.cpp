// The Stepper: preparation, edits after cuts, substepping, the snap-back rule, and one substep function
// per scheme (explicit Euler, midpoint and classic RK4 as in the thesis; symplectic Euler), and
// Provot's strain limit after a step when it is on.
#include "hapticut/physics/integrators.h"

#include <algorithm>
#include <cmath>

#include "hapticut/common/reserve.h"
#include "hapticut/physics/strain_limit.h"

namespace hapticut::physics {

void Stepper::setScheme(Scheme scheme) {
    scheme_ = scheme;
    preparedNodes_ = static_cast<std::size_t>(-1);
}

void Stepper::setToolStiffness(double stiffness_N_per_m) {
    toolStiffness_ = stiffness_N_per_m;
    preparedNodes_ = static_cast<std::size_t>(-1);
}

void Stepper::setActiveRegion(bool on) {
    activeRegion_ = on;
    region_.invalidate();
    ++layout_;
}

void Stepper::reserveFor(std::size_t n, std::size_t ns) {
    const std::size_t nodes = roomToGrow(n), springs = roomToGrow(ns);
    for (auto* buffer : {&x0_, &v0_, &xs_, &vs_, &a_, &dx_, &dv_}) reserveTouched(*buffer, nodes);
    reserveTouched(forces_, nodes);
    reserveTouched(allNodes_, nodes);
    reserveTouched(allSprings_, springs);
    reserveTouched(moved_, nodes);
    reserveTouched(snapped_, nodes);
    reserveTouched(visitedIn_, nodes);
    implicit_.reserve(nodes, springs);
    region_.reserve(nodes, springs);
    springsAt_.reserve(nodes, springs);
}

void Stepper::prepare(const MassSpringModel& model) {
    const std::size_t n = model.nodes.size(), ns = model.springs.size();
    reserveFor(n, ns);
    for (auto* buffer : {&x0_, &v0_, &xs_, &vs_, &a_, &dx_, &dv_}) buffer->resize(n);
    forces_.resize(n);
    stableDt_ = stableTimeStep(model, scheme_, toolStiffness_);
    rawStableDt_ = stableDt_ / kStableSafety;
    allNodes_.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) allNodes_[i] = i;
    allSprings_.resize(ns);
    for (std::uint32_t k = 0; k < ns; ++k) allSprings_[k] = k;
    implicit_.resize(n);
    springsAt_.build(model.springs, n);
    region_.reset(model);
    ++layout_;
    preparedNodes_ = n;
    preparedSprings_ = ns;
}

void Stepper::constantsChanged(const MassSpringModel& model, Scheme requested, double dt_s) {
    setScheme(resolveScheme(requested, model, dt_s, toolStiffness_));
    prepare(model);
}

void Stepper::lowerStableStepAt(const MassSpringModel& model, std::uint32_t i) {
    double k = 0, d = 0;
    for (std::uint32_t s : springsAt_.of(i)) k += model.springs.stiffness[s], d += model.springs.damping[s];
    const Nodes& n = model.nodes;
    lowerStableStepForNode(scheme_, rawStableDt_, n.inverseMass[i], n.anchorStiffness[i] + toolStiffness_,
                           n.anchorDamping[i], k, d);
}

void Stepper::topologyChanged(const MassSpringModel& model, std::span<const std::uint32_t> nodes,
                              std::span<const std::uint32_t> springs) {
    if (preparedNodes_ == static_cast<std::size_t>(-1) || model.nodes.size() < preparedNodes_ ||
        model.springs.size() < preparedSprings_) {
        prepare(model);  // never prepared, or the model shrank: not an edit this can follow
        return;
    }
    const std::size_t n = model.nodes.size(), ns = model.springs.size();
    if (n > x0_.capacity() || ns > springsAt_.springCapacity()) reserveFor(n, ns);
    for (auto* buffer : {&x0_, &v0_, &xs_, &vs_, &a_, &dx_, &dv_}) buffer->resize(n, Vec3::Zero());
    forces_.resize(n);
    for (auto i = static_cast<std::uint32_t>(allNodes_.size()); i < n; ++i) allNodes_.push_back(i);
    for (auto k = static_cast<std::uint32_t>(allSprings_.size()); k < ns; ++k) allSprings_.push_back(k);
    implicit_.resize(n);
    region_.resize(n, ns);
    ++layout_;  // the edited springs' ends moved
    springsAt_.update(model.springs, n, springs);
    visitedIn_.resize(n, 0);
    if (++visit_ == 0) std::fill(visitedIn_.begin(), visitedIn_.end(), 0), visit_ = 1;
    // The nodes whose modes may have changed: the listed ones and the ends of the listed springs, each
    // once (a cut lists a node again for every edit that touched it: eight times on average).
    auto visit = [&](std::uint32_t i) {
        if (visitedIn_[i] == visit_) return;
        visitedIn_[i] = visit_;
        lowerStableStepAt(model, i);
        region_.wake(i);  // falls asleep again at once if it is at rest with nothing pulling on it
    };
    for (std::uint32_t i : nodes) visit(i);
    for (std::uint32_t k : springs) visit(model.springs.a[k]), visit(model.springs.b[k]);
    stableDt_ = kStableSafety * rawStableDt_;
    preparedNodes_ = n;
    preparedSprings_ = ns;
}

int Stepper::substepsFor(double dt_s) const {
    if (scheme_ == Scheme::BackwardEuler || scheme_ == Scheme::Auto) return 1;
    if (!autoSubstep_ || stableDt_ <= 0 || dt_s <= stableDt_) return 1;
    // The small tolerance keeps an exact multiple (10 x the stable step) from rounding up to 11.
    return static_cast<int>(std::min(std::ceil(dt_s / stableDt_ * (1 - 1e-12)), 1e6));
}

SolveRegion Stepper::solveRegion() const {
    if (activeRegion_) return {region_.nodes(), region_.touched(), region_.springs(), layout_};
    return {allNodes_, allNodes_, allSprings_, layout_};
}

std::span<const std::uint32_t> Stepper::integratedNodes() const {
    return activeRegion_ ? region_.nodes() : std::span<const std::uint32_t>(allNodes_);
}

void Stepper::accelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v) {
    if (activeRegion_)
        computeActiveAccelerations(model, x, v, a_, region_.nodes(), region_.touched(), region_.springs(), forces_);
    else
        computeAccelerations(model, x, v, a_, forces_);
}

StepResult Stepper::step(MassSpringModel& model, double dt_s) {
    if (scheme_ == Scheme::Auto) setScheme(resolveScheme(Scheme::Auto, model, dt_s, toolStiffness_));
    if (preparedNodes_ != model.nodes.size() || preparedSprings_ != model.springs.size()) prepare(model);
    StepResult result;
    result.substeps = substepsFor(dt_s);
    Nodes& n = model.nodes;

    if (activeRegion_) {
        region_.admit(model, springsAt_);
        if (region_.version() != regionVersion_) regionVersion_ = region_.version(), ++layout_;
    }
    const std::span<const std::uint32_t> nodes = integratedNodes();
    for (std::uint32_t i : nodes) x0_[i] = n.position[i], v0_[i] = n.velocity[i];
    if (activeRegion_)
        for (std::uint32_t i : region_.touched())
            xs_[i] = n.position[i], vs_[i] = n.velocity[i];  // resting neighbours, read by every stage
    if (scheme_ == Scheme::BackwardEuler) {
        result.solve = implicit_.step(model, dt_s, solveRegion());
    } else {
        const double h = dt_s / result.substeps;
        for (int i = 0; i < result.substeps; ++i) substep(model, h);
    }
    if (strainLimit_ > 0) {
        // Over the springs the step integrated; a resting neighbour of the region stays at rest.
        const std::span<const std::uint32_t> springs =
            activeRegion_ ? region_.springs() : std::span<const std::uint32_t>(allSprings_);
        const std::span<const std::uint8_t> movable =
            activeRegion_ ? region_.awakeFlags() : std::span<const std::uint8_t>();
        limitStrain(model, springs, strainLimit_, movable);
    }

    snapped_.clear();
    for (std::uint32_t i : nodes) {
        if (!n.position[i].allFinite() || !n.velocity[i].allFinite()) result.finite = false;
        // R4: a node that is almost at rest is put back exactly at rest. dx_ and dv_, free once the
        // substeps are done, keep where the step took it.
        if ((n.position[i] - n.restPosition[i]).squaredNorm() < model.snapDistance_m * model.snapDistance_m &&
            n.velocity[i].squaredNorm() < model.snapSpeed_m_per_s * model.snapSpeed_m_per_s) {
            dx_[i] = n.position[i], dv_[i] = n.velocity[i];
            snapped_.push_back(i);  // reserved for every node: never allocates
            n.position[i] = n.restPosition[i];
            n.velocity[i] = Vec3::Zero();
        }
    }
    if (!result.finite) {
        // Roll back rather than let NaN spread through the model and into a device.
        for (std::uint32_t i : nodes) n.position[i] = x0_[i], n.velocity[i] = Vec3::Zero(), implicit_.forget(i);
        snapped_.clear();
    }
    if (activeRegion_) {
        moved_.assign(nodes.begin(), nodes.end());     // reserved for every node: never allocates
        accelerations(model, n.position, n.velocity);  // forces at the end state decide who sleeps and wakes
        // A node its springs pull off rest harder than its anchor holds within the snap distance is
        // left where the step took it. Put back, it could never leave rest where the pull gives way as
        // it moves (its place of balance is within the snap distance): it stayed awake, pulled, and put
        // back every step, and the solve worked its motion out only to have it undone. A 20 ms step of
        // a held press on the 1,000,000 heart took 28 iterations, 14 with this.
        for (std::uint32_t i : snapped_) {
            if (ActiveRegion::pulledOffRest(model, i, a_[i].norm() * n.mass[i]))
                n.position[i] = dx_[i], n.velocity[i] = dv_[i];
            else
                implicit_.forget(i);
        }
        region_.updateSleep(model, a_);
    } else {
        for (std::uint32_t i : snapped_) implicit_.forget(i);
    }
    return result;
}

void Stepper::substep(MassSpringModel& model, double h) {
    switch (scheme_) {
        case Scheme::ExplicitEuler: explicitEulerSubstep(model, h); break;
        case Scheme::SymplecticEuler: symplecticEulerSubstep(model, h); break;
        case Scheme::Midpoint: midpointSubstep(model, h); break;
        case Scheme::RungeKutta4: rungeKutta4Substep(model, h); break;
        case Scheme::BackwardEuler:
        case Scheme::Auto: break;  // solved in step(), never substepped
    }
}

void Stepper::explicitEulerSubstep(MassSpringModel& model, double h) {
    std::vector<Vec3>& x = model.nodes.position;
    std::vector<Vec3>& v = model.nodes.velocity;
    accelerations(model, x, v);
    for (std::uint32_t i : integratedNodes()) {
        x[i] += h * v[i];
        v[i] += h * a_[i];
    }
}

void Stepper::symplecticEulerSubstep(MassSpringModel& model, double h) {
    std::vector<Vec3>& x = model.nodes.position;
    std::vector<Vec3>& v = model.nodes.velocity;
    accelerations(model, x, v);
    for (std::uint32_t i : integratedNodes()) {
        v[i] += h * a_[i];
        x[i] += h * v[i];
    }
}

void Stepper::midpointSubstep(MassSpringModel& model, double h) {
    std::vector<Vec3>& x = model.nodes.position;
    std::vector<Vec3>& v = model.nodes.velocity;
    const std::span<const std::uint32_t> nodes = integratedNodes();
    accelerations(model, x, v);
    for (std::uint32_t i : nodes) {
        xs_[i] = x[i] + 0.5 * h * v[i];
        vs_[i] = v[i] + 0.5 * h * a_[i];
    }
    accelerations(model, xs_, vs_);
    for (std::uint32_t i : nodes) {
        x[i] += h * vs_[i];
        v[i] += h * a_[i];
    }
}

namespace {

/// RK4's first stage over n coordinates: the next stage's state (xs, vs) and the sums in (x, v).
void firstStage(std::size_t n, double half, double sixth, const double* __restrict a, double* __restrict x,
                double* __restrict v, double* __restrict xs, double* __restrict vs) {
    for (std::size_t i = 0; i < n; ++i) {
        xs[i] = x[i] + half * v[i];
        vs[i] = v[i] + half * a[i];
        x[i] += sixth * v[i];
        v[i] += sixth * a[i];
    }
}

/// A later stage: its weight in the sums, and (unless last) the next stage's state from (x0, v0).
void laterStage(std::size_t n, double weight, double next, bool last, const double* __restrict a,
                const double* __restrict x0, const double* __restrict v0, double* __restrict x, double* __restrict v,
                double* __restrict xs, double* __restrict vs) {
    for (std::size_t i = 0; i < n; ++i) {
        x[i] += weight * vs[i];
        v[i] += weight * a[i];
    }
    if (!last)
        for (std::size_t i = 0; i < n; ++i) {
            xs[i] = x0[i] + next * vs[i];
            vs[i] = v0[i] + next * a[i];
        }
}

}  // namespace

void Stepper::rungeKutta4Substep(MassSpringModel& model, double h) {
    // Classic RK4 on (x, v): stage k_j = (v_j, a(x_j, v_j)); the weighted sums of the stages build up in
    // x, v directly, so that only one stage state (xs_, vs_) is live at a time.
    std::vector<Vec3>& x = model.nodes.position;
    std::vector<Vec3>& v = model.nodes.velocity;
    const double half = 0.5 * h, sixth = h / 6;
    if (!activeRegion_) {
        // Every node: the same sums over plain arrays of coordinates, which vectorise.
        const std::size_t n = 3 * x.size();
        std::copy_n(coordinates(x.data()), n, coordinates(dx_.data())),
            std::copy_n(coordinates(v.data()), n, coordinates(dv_.data()));
        accelerations(model, x, v);
        firstStage(n, half, sixth, coordinates(a_.data()), coordinates(x.data()), coordinates(v.data()),
                   coordinates(xs_.data()), coordinates(vs_.data()));
        for (int stage = 2; stage <= 4; ++stage) {
            accelerations(model, xs_, vs_);
            laterStage(n, stage == 4 ? sixth : 2 * sixth, stage == 3 ? h : half, stage == 4, coordinates(a_.data()),
                       coordinates(dx_.data()), coordinates(dv_.data()), coordinates(x.data()), coordinates(v.data()),
                       coordinates(xs_.data()), coordinates(vs_.data()));
        }
        return;
    }
    const std::span<const std::uint32_t> nodes = integratedNodes();
    for (std::uint32_t i : nodes) dx_[i] = x[i], dv_[i] = v[i];  // the state at the start of this substep
    accelerations(model, x, v);
    for (std::uint32_t i : nodes) {
        xs_[i] = x[i] + half * v[i];
        vs_[i] = v[i] + half * a_[i];
        x[i] += sixth * v[i];
        v[i] += sixth * a_[i];
    }
    for (int stage = 2; stage <= 4; ++stage) {
        accelerations(model, xs_, vs_);
        const double weight = stage == 4 ? sixth : 2 * sixth;
        const double next = stage == 3 ? h : half;  // stage 4 is taken from the full-step state
        for (std::uint32_t i : nodes) {
            const Vec3 vi = vs_[i];
            x[i] += weight * vi;
            v[i] += weight * a_[i];
            if (stage < 4) {
                xs_[i] = dx_[i] + next * vi;
                vs_[i] = dv_[i] + next * a_[i];
            }
        }
    }
}

}  // namespace hapticut::physics
