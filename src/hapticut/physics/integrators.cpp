// The Stepper: preparation, edits after cuts, substepping, the snap-back rule, and one substep function
// per scheme (explicit Euler, midpoint and classic RK4 as in the thesis; symplectic Euler), and
// Provot's strain limit after a step when it is on.
#include "hapticut/physics/integrators.h"

#include <algorithm>
#include <cmath>

#include "hapticut/common/reserve.h"
#include "hapticut/physics/spring_kernels.h"
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
    for (auto* buffer : {&x0_, &xs_, &vs_, &a_, &dx_, &dv_}) reserveTouched(*buffer, nodes);
    reserveTouched(forces_, nodes);
    reserveTouched(allNodes_, nodes);
    reserveTouched(allSprings_, springs);
    reserveTouched(moved_, nodes);
    reserveTouched(snapped_, nodes);
    reserveTouched(atRest_, nodes);
    reserveTouched(visitedIn_, nodes);
    implicit_.reserve(nodes, springs);
    region_.reserve(nodes, springs);
    springsAt_.reserve(nodes, springs);
}

void Stepper::prepare(const MassSpringModel& model) {
    const std::size_t n = model.nodes.size(), ns = model.springs.size();
    reserveFor(n, ns);
    for (auto* buffer : {&x0_, &xs_, &vs_, &a_, &dx_, &dv_}) buffer->resize(n);
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
    for (auto* buffer : {&x0_, &xs_, &vs_, &a_, &dx_, &dv_}) buffer->resize(n, Vec3::Zero());
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

void Stepper::endStateForces(const MassSpringModel& model) {
    // Only the nodes at rest need them: the awake ones there (snapped, or not moved) and the resting
    // neighbours. Summed over their own springs, that is a small part of the region's springs: in a press
    // held on the 100,000 heart, 220 resting neighbours and no awake node at rest, against 8,059 springs
    // that the pass over the region sums. Where it is not, or a tool loads one of them, the region's pass.
    const Nodes& n = model.nodes;
    const std::span<const std::uint8_t> awake = region_.awakeFlags();
    atRest_.clear();
    std::size_t springs = 0;
    for (const std::uint32_t i : region_.touched()) {
        if (awake[i] && !ActiveRegion::atRest(n, i)) continue;
        atRest_.push_back(i);  // reserved for every node: never allocates
        springs += springsAt_.of(i).size();
    }
    bool loaded = false;
    for (const PointSpring& tool : model.tools)
        for (std::uint32_t c = 0; tool.active && c < tool.count; ++c) loaded |= ActiveRegion::atRest(n, tool.nodes[c]);
    if (loaded || 2 * springs > region_.springs().size())
        accelerations(model, n.position, n.velocity);
    else
        computeListedAccelerations(model, n.position, n.velocity, a_, atRest_, awake, springsAt_);
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
    {
        // Where a step that goes non-finite puts the nodes back, their velocities zeroed.
        // Held here: through the members, every store reloaded the arrays' addresses.
        const Vec3* __restrict x = n.position.data();
        Vec3* __restrict x0 = x0_.data();
        for (std::uint32_t i : nodes) x0[i] = x[i];
    }
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
    // Read once: the list's growth below made the loop read them again for every node; the arrays
    // held for the same reason.
    const double snapDistance2 = model.snapDistance_m * model.snapDistance_m;
    const double snapSpeed2 = model.snapSpeed_m_per_s * model.snapSpeed_m_per_s;
    bool finite = true;
    {
        Vec3* __restrict x = n.position.data();
        Vec3* __restrict v = n.velocity.data();
        const Vec3* __restrict rest = n.restPosition.data();
        Vec3* __restrict keptX = dx_.data();
        Vec3* __restrict keptV = dv_.data();
        for (std::uint32_t i : nodes) {
            finite &= x[i].allFinite() && v[i].allFinite();
            // R4: a node that is almost at rest is put back exactly at rest. dx_ and dv_, free once the
            // substeps are done, keep where the step took it.
            if ((x[i] - rest[i]).squaredNorm() < snapDistance2 && v[i].squaredNorm() < snapSpeed2) {
                keptX[i] = x[i], keptV[i] = v[i];
                snapped_.push_back(i);  // reserved for every node: never allocates
                x[i] = rest[i];
                v[i] = Vec3::Zero();
            }
        }
    }
    result.finite = result.finite && finite;
    if (!result.finite) {
        // Roll back rather than let NaN spread through the model and into a device.
        for (std::uint32_t i : nodes) n.position[i] = x0_[i], n.velocity[i] = Vec3::Zero(), implicit_.forget(i);
        snapped_.clear();
    }
    if (activeRegion_) {
        moved_.assign(nodes.begin(), nodes.end());  // reserved for every node: never allocates
        endStateForces(model);                      // forces at the end state decide who sleeps and wakes
        // A node its springs pull off rest (alone, it would settle beyond the snap distance) is left
        // where the step took it. Put back, it could never leave rest where the pull gives way as it
        // moves (its place of balance is within the snap distance): it stayed awake, pulled, and put
        // back every step, and the solve worked its motion out only to have it undone. A 20 ms step of
        // a held press on the 1,000,000 heart took 28 iterations, 14 with this.
        for (std::uint32_t i : snapped_) {
            if (ActiveRegion::pulledOffRest(model, springsAt_, i, a_[i] * n.mass[i]))
                n.position[i] = dx_[i], n.velocity[i] = dv_[i];
            else
                implicit_.forget(i);
        }
        region_.updateSleep(model, springsAt_, a_);
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

/// RK4's start over every node: the substep's first state kept in (x0, v0) and the first stage's
/// positioning forces in f.
void startRungeKutta4(const Nodes& n, std::size_t count, const double* __restrict x, const double* __restrict v,
                      double* __restrict x0, double* __restrict v0, ForceRow* __restrict f) {
    std::copy_n(x, 3 * count, x0), std::copy_n(v, 3 * count, v0);
    startWithPositioningForces(n, count, x, v, f);
}

/// RK4's pass over every node once stage kStage's forces are in f: the accelerations (a = F/m + g, as
/// computeAccelerations ends), the stage's weight in the sums (x, v), and, unless it is the last stage,
/// the next stage's state (xs, vs) from (x0, v0) and its positioning forces in f. One pass where
/// separate ones for the forces, the accelerations and the sums read and wrote the arrays three times
/// over (a fully awake 100,000 heart's step 5.0 → 4.1 ms); each coordinate's operations are those of
/// the separate passes, in their order.
template <int kStage>
void rungeKutta4Stage(const Nodes& n, const Vec3& gravity, std::size_t count, double h, ForceRow* __restrict f,
                      double* __restrict x, double* __restrict v, double* __restrict xs, double* __restrict vs,
                      const double* __restrict x0, const double* __restrict v0) {
    const double half = 0.5 * h, sixth = h / 6;
    const double weight = kStage == 1 || kStage == 4 ? sixth : 2 * sixth;
    const double next = kStage == 3 ? h : half;  // stage 4 is taken from the full-step state
    const double* __restrict inverseMass = n.inverseMass.data();
    const double* __restrict rest = coordinates(n.restPosition.data());
    const double* __restrict external = coordinates(n.externalForce.data());
    const double* __restrict anchorStiffness = n.anchorStiffness.data();
    const double* __restrict anchorDamping = n.anchorDamping.data();
    const double g[3] = {gravity.x(), gravity.y(), gravity.z()};
    for (std::size_t i = 0; i < count; ++i) {
        const double m = inverseMass[i], k = anchorStiffness[i], d = anchorDamping[i];
        const double force[3] = {f[i].x, f[i].y, f[i].z};
        double nextForce[4] = {0, 0, 0, 0};
        for (std::size_t c = 0; c < 3; ++c) {
            const std::size_t j = 3 * i + c;
            const double a = acceleration(m, force[c], g[c]);
            double nextX, nextV;
            if constexpr (kStage == 1) {
                nextX = x[j] + half * v[j], nextV = v[j] + half * a;
                x[j] += weight * v[j];
                v[j] += weight * a;
            } else {
                nextX = x0[j] + next * vs[j], nextV = v0[j] + next * a;
                x[j] += weight * vs[j];
                v[j] += weight * a;
            }
            if constexpr (kStage < 4) {
                xs[j] = nextX, vs[j] = nextV;
                nextForce[c] = positioningForce(external[j], k, d, nextX - rest[j], nextV);
            }
        }
        if constexpr (kStage < 4) f[i] = {nextForce[0], nextForce[1], nextForce[2], nextForce[3]};
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
        // Every node: computeAccelerations' terms with its passes over the nodes folded into the sums'.
        const Nodes& n = model.nodes;
        const std::size_t count = x.size();
        double *px = coordinates(x.data()), *pv = coordinates(v.data());
        double *pxs = coordinates(xs_.data()), *pvs = coordinates(vs_.data());
        double *px0 = coordinates(dx_.data()), *pv0 = coordinates(dv_.data());
        const kernels::SpringArrays springs = springArrays(model.springs);
        const std::span<ForceRow> f(forces_.data(), count);
        startRungeKutta4(n, count, px, pv, px0, pv0, f.data());
        auto stageForces = [&](std::span<const Vec3> sx, std::span<const Vec3> sv) {
            kernels::addSpringForces(springs, model.springs.size(), coordinates(sx.data()), coordinates(sv.data()),
                                     f.data());
            for (const PointSpring& tool : model.tools) tool.addReaction(sx, f);  // R9, as computeAccelerations
        };
        const Vec3 g = model.gravity_m_per_s2;
        stageForces(x, v);
        rungeKutta4Stage<1>(n, g, count, h, f.data(), px, pv, pxs, pvs, px0, pv0);
        stageForces(xs_, vs_);
        rungeKutta4Stage<2>(n, g, count, h, f.data(), px, pv, pxs, pvs, px0, pv0);
        stageForces(xs_, vs_);
        rungeKutta4Stage<3>(n, g, count, h, f.data(), px, pv, pxs, pvs, px0, pv0);
        stageForces(xs_, vs_);
        rungeKutta4Stage<4>(n, g, count, h, f.data(), px, pv, pxs, pvs, px0, pv0);
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
