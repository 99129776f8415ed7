// Explicit Euler, midpoint, classic RK4 and symplectic Euler, with a stability estimate.
#include "hapticut/physics/integrators.h"

#include <algorithm>
#include <cmath>
#include <complex>

#include "hapticut/common/reserve.h"
#include "hapticut/physics/spring_forces.h"

namespace hapticut::physics {

std::string_view schemeName(Scheme scheme) {
    switch (scheme) {
        case Scheme::ExplicitEuler: return "euler";
        case Scheme::Midpoint: return "midpoint";
        case Scheme::RungeKutta4: return "rk4";
        case Scheme::SymplecticEuler: return "symplectic";
    }
    return "?";
}

std::optional<Scheme> parseScheme(std::string_view name) {
    for (Scheme s : {Scheme::ExplicitEuler, Scheme::Midpoint, Scheme::RungeKutta4, Scheme::SymplecticEuler})
        if (schemeName(s) == name) return s;
    return std::nullopt;
}

namespace {

/// Is the damped oscillator x'' = -w2 x - c x' stable under `scheme` with step h?
bool modeStable(Scheme scheme, double w2, double c, double h) {
    if (scheme == Scheme::SymplecticEuler) {
        // Its update matrix has determinant 1 - c h and trace 2 - w2 h² - c h; both eigenvalues lie in
        // the unit disc exactly when c h <= 2 and w2 h² + 2 c h <= 4.
        return c * h <= 2 && w2 * h * h + 2 * c * h <= 4;
    }
    const std::complex<double> disc = std::sqrt(std::complex<double>(c * c / 4 - w2));
    for (const std::complex<double> lambda : {-c / 2 + disc, -c / 2 - disc}) {
        const std::complex<double> z = lambda * h;
        std::complex<double> r;  // the method's amplification factor R(z) for y' = lambda y
        switch (scheme) {
            case Scheme::ExplicitEuler: r = 1.0 + z; break;
            case Scheme::Midpoint: r = 1.0 + z + z * z / 2.0; break;
            default: r = 1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0; break;
        }
        if (std::abs(r) > 1 + 1e-12) return false;
    }
    return true;
}

double largestStableStep(Scheme scheme, double w2, double c) {
    if (w2 <= 0 && c <= 0) return 1e9;
    double lo = 0, hi = 10;
    if (modeStable(scheme, w2, c, hi)) return hi;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (modeStable(scheme, w2, c, mid) ? lo : hi) = mid;
    }
    return lo;
}

/// Lowers dt to what one node's modes allow: its positioning mode, and its highest mode against its
/// neighbours (springs summing to k, d). A mode still stable at dt cannot lower it: one check instead
/// of a bisection for almost every node.
void lowerForNode(Scheme scheme, double& dt, double inverse_mass, double anchor_k, double anchor_d, double k, double d) {
    if (inverse_mass == 0) return;
    auto lower = [&](double w2, double c) {
        if (dt < 1e9 && modeStable(scheme, w2, c, dt)) return;
        dt = std::min(dt, largestStableStep(scheme, w2, c));
    };
    lower(anchor_k * inverse_mass, anchor_d * inverse_mass);
    lower((anchor_k + 2 * k) * inverse_mass, (anchor_d + 2 * d) * inverse_mass);
}

constexpr double kStableSafety = 0.9;

}  // namespace

double stableTimeStep(const MassSpringModel& model, Scheme scheme, double extra_stiffness_N_per_m) {
    const Nodes& n = model.nodes;
    const Springs& s = model.springs;
    std::vector<double> k(n.size(), 0.0), d(n.size(), 0.0);
    for (std::size_t i = 0; i < s.size(); ++i) {
        k[s.a[i]] += s.stiffness[i], k[s.b[i]] += s.stiffness[i];
        d[s.a[i]] += s.damping[i], d[s.b[i]] += s.damping[i];
    }
    double dt = 1e9;
    for (std::size_t i = 0; i < n.size(); ++i)
        lowerForNode(scheme, dt, n.inverseMass[i], n.anchorStiffness[i] + extra_stiffness_N_per_m, n.anchorDamping[i], k[i], d[i]);
    return kStableSafety * dt;
}

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
    activeDirty_ = true;
}

void Stepper::reserveFor(std::size_t n, std::size_t ns) {
    const std::size_t nodes = roomToGrow(n), springs = roomToGrow(ns);
    for (auto* buffer : {&x0_, &v0_, &xs_, &vs_, &a_, &dx_, &dv_}) reserveTouched(*buffer, nodes);
    for (auto* list : {&allNodes_, &activeNodes_, &touchedNodes_, &wakeList_}) reserveTouched(*list, nodes);
    for (auto* marks : {&awake_, &wakeNext_, &touchedMark_}) reserveTouched(*marks, nodes);
    nodeSprings_.reserve(nodes);
    reserveTouched(springMark_, springs);
    reserveTouched(activeSprings_, springs);
    reserveTouched(springEnds_, springs);
}

void Stepper::prepare(const MassSpringModel& model) {
    const std::size_t n = model.nodes.size(), ns = model.springs.size();
    reserveFor(n, ns);
    for (auto* buffer : {&x0_, &v0_, &xs_, &vs_, &a_, &dx_, &dv_}) buffer->resize(n);
    stableDt_ = stableTimeStep(model, scheme_, toolStiffness_);
    rawStableDt_ = stableDt_ / kStableSafety;
    allNodes_.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) allNodes_[i] = i;
    // Active-region bookkeeping, sized once so that stepping never allocates.
    awake_.assign(n, 0);
    wakeNext_.assign(n, 0);
    touchedMark_.assign(n, 0);
    springMark_.assign(ns, 0);
    activeNodes_.clear();
    touchedNodes_.clear();
    activeSprings_.clear();
    nodeSprings_.assign(n, {});
    springEnds_.resize(ns);
    for (std::uint32_t k = 0; k < ns; ++k) {
        springEnds_[k] = {model.springs.a[k], model.springs.b[k]};
        nodeSprings_[model.springs.a[k]].push_back(k), nodeSprings_[model.springs.b[k]].push_back(k);
    }
    // Whatever is not at rest starts awake.
    wakeList_.clear();
    for (std::uint32_t i = 0; i < n; ++i)
        if (model.nodes.position[i] != model.nodes.restPosition[i] || model.nodes.velocity[i] != Vec3::Zero()) wake(i);
    activeDirty_ = true;
    preparedNodes_ = n;
    preparedSprings_ = ns;
}

void Stepper::lowerStableStepAt(const MassSpringModel& model, std::uint32_t i) {
    double k = 0, d = 0;
    for (std::uint32_t s : nodeSprings_[i]) k += model.springs.stiffness[s], d += model.springs.damping[s];
    const Nodes& n = model.nodes;
    lowerForNode(scheme_, rawStableDt_, n.inverseMass[i], n.anchorStiffness[i] + toolStiffness_, n.anchorDamping[i], k, d);
}

void Stepper::topologyChanged(const MassSpringModel& model, std::span<const std::uint32_t> nodes, std::span<const std::uint32_t> springs) {
    if (preparedNodes_ == static_cast<std::size_t>(-1) || model.nodes.size() < preparedNodes_ || model.springs.size() < preparedSprings_) {
        prepare(model);  // never prepared, or the model shrank: not an edit this can follow
        return;
    }
    const std::size_t n = model.nodes.size(), ns = model.springs.size();
    if (n > x0_.capacity() || ns > springEnds_.capacity()) reserveFor(n, ns);
    for (auto* buffer : {&x0_, &v0_, &xs_, &vs_, &a_, &dx_, &dv_}) buffer->resize(n, Vec3::Zero());
    for (auto i = static_cast<std::uint32_t>(allNodes_.size()); i < n; ++i) allNodes_.push_back(i);
    for (auto* marks : {&awake_, &wakeNext_, &touchedMark_}) marks->resize(n, 0);
    springMark_.resize(ns, 0);
    nodeSprings_.resize(n);
    constexpr std::uint32_t kNone = 0xffffffffu;
    springEnds_.resize(ns, {kNone, kNone});
    // Move each listed spring between the nodes' lists when its ends changed.
    for (std::uint32_t k : springs) {
        const std::array<std::uint32_t, 2> now{model.springs.a[k], model.springs.b[k]};
        std::array<std::uint32_t, 2>& seen = springEnds_[k];
        if (seen == now) continue;
        for (std::uint32_t end : seen) {
            if (end == kNone) continue;
            auto& list = nodeSprings_[end];
            list.erase(std::remove(list.begin(), list.end(), k), list.end());
        }
        for (std::uint32_t end : now) nodeSprings_[end].push_back(k);
        seen = now;
    }
    // The nodes whose modes may have changed: the listed ones and the ends of the listed springs.
    auto visit = [&](std::uint32_t i) {
        lowerStableStepAt(model, i);
        wake(i);  // falls asleep again at once if it is at rest with nothing pulling on it
    };
    for (std::uint32_t i : nodes) visit(i);
    for (std::uint32_t k : springs) visit(model.springs.a[k]), visit(model.springs.b[k]);
    stableDt_ = kStableSafety * rawStableDt_;
    activeDirty_ = true;
    preparedNodes_ = n;
    preparedSprings_ = ns;
}

void Stepper::wake(std::uint32_t node) {
    if (node >= wakeNext_.size() || wakeNext_[node]) return;
    wakeNext_[node] = 1;
    wakeList_.push_back(node);  // reserved for every node in prepare(): never allocates
}

int Stepper::substepsFor(double dt_s) const {
    if (!autoSubstep_ || stableDt_ <= 0 || dt_s <= stableDt_) return 1;
    // The small tolerance keeps an exact multiple (10 x the stable step) from rounding up to 11.
    return static_cast<int>(std::min(std::ceil(dt_s / stableDt_ * (1 - 1e-12)), 1e6));
}

void Stepper::rebuildActiveLists(const MassSpringModel& model) {
    for (std::uint32_t k : activeSprings_) springMark_[k] = 0;
    for (std::uint32_t i : touchedNodes_) touchedMark_[i] = 0;
    activeSprings_.clear();
    touchedNodes_.clear();
    for (std::uint32_t i : activeNodes_) {
        touchedMark_[i] = 1;
        touchedNodes_.push_back(i);
    }
    for (std::uint32_t i : activeNodes_)
        for (const std::uint32_t k : nodeSprings_[i]) {
            if (springMark_[k]) continue;
            springMark_[k] = 1;
            activeSprings_.push_back(k);
            for (std::uint32_t j : {model.springs.a[k], model.springs.b[k]})
                if (!touchedMark_[j]) touchedMark_[j] = 1, touchedNodes_.push_back(j);
        }
    activeDirty_ = false;
}

void Stepper::accelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v) {
    if (activeRegion_) computeActiveAccelerations(model, x, v, a_, activeNodes_, touchedNodes_, activeSprings_);
    else computeAccelerations(model, x, v, a_);
}

void Stepper::updateSleep(const MassSpringModel& model) {
    // Resting neighbours that a spring pulls harder than their anchor could hold within the snap
    // distance wake for the next step (a one-step delay, far below what the tissue does in 1 ms).
    const Nodes& n = model.nodes;
    for (std::uint32_t i : touchedNodes_)
        if (!awake_[i] && a_[i].norm() > n.anchorStiffness[i] * model.snapDistance_m) wakeNext_[i] = 1;
    // Awake nodes that the snap rule holds at rest, with a negligible force on them, fall asleep.
    std::size_t kept = 0;
    for (std::uint32_t i : activeNodes_) {
        const bool atRest = n.position[i] == n.restPosition[i] && n.velocity[i] == Vec3::Zero();
        const bool pulled = a_[i].norm() * n.mass[i] > n.anchorStiffness[i] * model.snapDistance_m;
        if (atRest && !pulled && !wakeNext_[i]) {
            awake_[i] = 0;
            activeDirty_ = true;
        } else {
            activeNodes_[kept++] = i;
        }
    }
    activeNodes_.resize(kept);
}

StepResult Stepper::step(MassSpringModel& model, double dt_s) {
    if (preparedNodes_ != model.nodes.size() || preparedSprings_ != model.springs.size()) prepare(model);
    StepResult result;
    result.substeps = substepsFor(dt_s);
    Nodes& n = model.nodes;

    if (activeRegion_) {
        // Only candidates are looked at, so this stays proportional to the region: the tool's nodes,
        // the resting neighbours flagged by updateSleep, and explicit wake() calls.
        auto admit = [&](std::uint32_t i) {
            if (wakeNext_[i] && !awake_[i]) {
                awake_[i] = 1;
                activeNodes_.push_back(i);
                activeDirty_ = true;
            }
            wakeNext_[i] = 0;
        };
        for (const PointSpring& tool : model.tools) {
            if (!tool.active) continue;
            for (std::uint32_t i : tool.nodes) {
                // The tool's nodes and their neighbours are always awake: within one step a push
                // travels further than the one ring the region grows by per step.
                wakeNext_[i] = 1;
                admit(i);
                for (const std::uint32_t k : nodeSprings_[i]) {
                    const std::uint32_t j = model.springs.a[k] == i ? model.springs.b[k] : model.springs.a[k];
                    wakeNext_[j] = 1;
                    admit(j);
                }
            }
        }
        for (std::size_t k = 0; k < touchedNodes_.size(); ++k) admit(touchedNodes_[k]);
        for (std::uint32_t i : wakeList_) admit(i);
        wakeList_.clear();
        if (activeDirty_) rebuildActiveLists(model);
    }
    const std::span<const std::uint32_t> nodes = activeRegion_ ? std::span<const std::uint32_t>(activeNodes_) : std::span<const std::uint32_t>(allNodes_);

    for (std::uint32_t i : nodes) x0_[i] = n.position[i], v0_[i] = n.velocity[i];
    if (activeRegion_)
        for (std::uint32_t i : touchedNodes_) xs_[i] = n.position[i], vs_[i] = n.velocity[i];  // resting neighbours, read by every stage
    const double h = dt_s / result.substeps;
    for (int i = 0; i < result.substeps; ++i) substep(model, h);

    for (std::uint32_t i : nodes) {
        if (!n.position[i].allFinite() || !n.velocity[i].allFinite()) result.finite = false;
        // R4: a node that is almost at rest is put back exactly at rest.
        if ((n.position[i] - n.restPosition[i]).squaredNorm() < model.snapDistance_m * model.snapDistance_m &&
            n.velocity[i].squaredNorm() < model.snapSpeed_m_per_s * model.snapSpeed_m_per_s) {
            n.position[i] = n.restPosition[i];
            n.velocity[i] = Vec3::Zero();
        }
    }
    if (!result.finite) {
        // Roll back rather than let NaN spread through the model and into a device.
        for (std::uint32_t i : nodes) n.position[i] = x0_[i], n.velocity[i] = Vec3::Zero();
    }
    if (activeRegion_) {
        accelerations(model, n.position, n.velocity);  // forces at the end state decide who sleeps and wakes
        updateSleep(model);
    }
    return result;
}

void Stepper::substep(MassSpringModel& model, double h) {
    Nodes& n = model.nodes;
    std::vector<Vec3>& x = n.position;
    std::vector<Vec3>& v = n.velocity;
    const std::span<const std::uint32_t> nodes = activeRegion_ ? std::span<const std::uint32_t>(activeNodes_) : std::span<const std::uint32_t>(allNodes_);
    switch (scheme_) {
        case Scheme::ExplicitEuler:
            accelerations(model, x, v);
            for (std::uint32_t i : nodes) {
                x[i] += h * v[i];
                v[i] += h * a_[i];
            }
            break;
        case Scheme::SymplecticEuler:
            accelerations(model, x, v);
            for (std::uint32_t i : nodes) {
                v[i] += h * a_[i];
                x[i] += h * v[i];
            }
            break;
        case Scheme::Midpoint:
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
            break;
        case Scheme::RungeKutta4: {
            // Classic RK4 on (x, v): stage k_j = (v_j, a(x_j, v_j)); the weighted sums of the stages
            // build up in x, v directly, so that only one stage state (xs_, vs_) is live at a time.
            for (std::uint32_t i : nodes) dx_[i] = x[i], dv_[i] = v[i];  // the state at the start of this substep
            const double half = 0.5 * h, sixth = h / 6;
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
            break;
        }
    }
}

}  // namespace hapticut::physics
