// Explicit Euler, midpoint, classic RK4 and symplectic Euler, with a stability estimate.
#include "hapticut/physics/integrators.h"

#include <algorithm>
#include <cmath>
#include <complex>

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
    for (std::size_t i = 0; i < n.size(); ++i) {
        const double im = n.inverseMass[i];
        if (im == 0) continue;
        const double anchor = n.anchorStiffness[i] + extra_stiffness_N_per_m;
        dt = std::min(dt, largestStableStep(scheme, anchor * im, n.anchorDamping[i] * im));
        dt = std::min(dt, largestStableStep(scheme, (anchor + 2 * k[i]) * im, (n.anchorDamping[i] + 2 * d[i]) * im));
    }
    return 0.9 * dt;
}

void Stepper::setScheme(Scheme scheme) {
    scheme_ = scheme;
    preparedNodes_ = static_cast<std::size_t>(-1);
}

void Stepper::setToolStiffness(double stiffness_N_per_m) {
    toolStiffness_ = stiffness_N_per_m;
    preparedNodes_ = static_cast<std::size_t>(-1);
}

void Stepper::prepare(const MassSpringModel& model) {
    const std::size_t n = model.nodes.size();
    for (auto* buffer : {&x0_, &v0_, &xs_, &vs_, &a_, &dx_, &dv_}) buffer->resize(n);
    stableDt_ = stableTimeStep(model, scheme_, toolStiffness_);
    preparedNodes_ = n;
    preparedSprings_ = model.springs.size();
}

int Stepper::substepsFor(double dt_s) const {
    if (!autoSubstep_ || stableDt_ <= 0 || dt_s <= stableDt_) return 1;
    // The small tolerance keeps an exact multiple (10 x the stable step) from rounding up to 11.
    return static_cast<int>(std::min(std::ceil(dt_s / stableDt_ * (1 - 1e-12)), 1e6));
}

StepResult Stepper::step(MassSpringModel& model, double dt_s) {
    if (preparedNodes_ != model.nodes.size() || preparedSprings_ != model.springs.size()) prepare(model);
    StepResult result;
    result.substeps = substepsFor(dt_s);
    Nodes& n = model.nodes;
    std::copy(n.position.begin(), n.position.end(), x0_.begin());
    std::copy(n.velocity.begin(), n.velocity.end(), v0_.begin());
    const double h = dt_s / result.substeps;
    for (int i = 0; i < result.substeps; ++i) substep(model, h);

    for (std::size_t i = 0; i < n.size(); ++i) {
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
        std::copy(x0_.begin(), x0_.end(), n.position.begin());
        std::fill(n.velocity.begin(), n.velocity.end(), Vec3::Zero());
    }
    return result;
}

void Stepper::substep(MassSpringModel& model, double h) {
    Nodes& n = model.nodes;
    std::vector<Vec3>& x = n.position;
    std::vector<Vec3>& v = n.velocity;
    const std::size_t count = n.size();
    switch (scheme_) {
        case Scheme::ExplicitEuler:
            computeAccelerations(model, x, v, a_);
            for (std::size_t i = 0; i < count; ++i) {
                x[i] += h * v[i];
                v[i] += h * a_[i];
            }
            break;
        case Scheme::SymplecticEuler:
            computeAccelerations(model, x, v, a_);
            for (std::size_t i = 0; i < count; ++i) {
                v[i] += h * a_[i];
                x[i] += h * v[i];
            }
            break;
        case Scheme::Midpoint:
            computeAccelerations(model, x, v, a_);
            for (std::size_t i = 0; i < count; ++i) {
                xs_[i] = x[i] + 0.5 * h * v[i];
                vs_[i] = v[i] + 0.5 * h * a_[i];
            }
            computeAccelerations(model, xs_, vs_, a_);
            for (std::size_t i = 0; i < count; ++i) {
                x[i] += h * vs_[i];
                v[i] += h * a_[i];
            }
            break;
        case Scheme::RungeKutta4: {
            // Classic RK4 on (x, v): stage k_j = (v_j, a(x_j, v_j)); the weighted sums of the stages
            // build up in dx_, dv_ so that only one stage state (xs_, vs_) is live at a time.
            std::copy(x.begin(), x.end(), dx_.begin());  // x at the start of this substep
            std::copy(v.begin(), v.end(), dv_.begin());
            const double half = 0.5 * h, sixth = h / 6;
            computeAccelerations(model, x, v, a_);
            for (std::size_t i = 0; i < count; ++i) {
                xs_[i] = x[i] + half * v[i];
                vs_[i] = v[i] + half * a_[i];
                x[i] += sixth * v[i];
                v[i] += sixth * a_[i];
            }
            for (int stage = 2; stage <= 4; ++stage) {
                computeAccelerations(model, xs_, vs_, a_);
                const double weight = stage == 4 ? sixth : 2 * sixth;
                const double next = stage == 3 ? h : half;  // stage 4 is taken from the full-step state
                for (std::size_t i = 0; i < count; ++i) {
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
