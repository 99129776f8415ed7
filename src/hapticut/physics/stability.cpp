// Linear stability of each scheme on each node's local modes.
#include "hapticut/physics/stability.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

#include "hapticut/common/line_reader.h"

namespace hapticut::physics {

bool modeStable(Scheme scheme, double w2, double c, double h_s) {
    const double h = h_s;
    if (scheme == Scheme::BackwardEuler || scheme == Scheme::Auto) return true;  // Auto resolves before a step
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

void lowerStableStepForNode(Scheme scheme, double& dt_s, double inverse_mass, double anchor_k, double anchor_d,
                            double k, double d) {
    if (inverse_mass == 0 || scheme == Scheme::BackwardEuler) return;
    // A mode still stable at dt cannot lower it: one check instead of a bisection for almost every node.
    auto lower = [&](double w2, double c) {
        if (dt_s < 1e9 && modeStable(scheme, w2, c, dt_s)) return;
        dt_s = std::min(dt_s, largestStableStep(scheme, w2, c));
    };
    lower(anchor_k * inverse_mass, anchor_d * inverse_mass);
    lower((anchor_k + 2 * k) * inverse_mass, (anchor_d + 2 * d) * inverse_mass);
}

double stableTimeStep(const MassSpringModel& model, Scheme scheme, double extra_stiffness_N_per_m) {
    if (scheme == Scheme::BackwardEuler) return kStableSafety * 1e9;
    const Nodes& n = model.nodes;
    const Springs& s = model.springs;
    std::vector<double> k(n.size(), 0.0), d(n.size(), 0.0);
    for (std::size_t i = 0; i < s.size(); ++i) {
        k[s.a[i]] += s.stiffness[i], k[s.b[i]] += s.stiffness[i];
        d[s.a[i]] += s.damping[i], d[s.b[i]] += s.damping[i];
    }
    double dt = 1e9;
    for (std::size_t i = 0; i < n.size(); ++i)
        lowerStableStepForNode(scheme, dt, n.inverseMass[i], n.anchorStiffness[i] + extra_stiffness_N_per_m,
                               n.anchorDamping[i], k[i], d[i]);
    return kStableSafety * dt;
}

Scheme resolveScheme(Scheme requested, const MassSpringModel& model, double dt_s, double extra_stiffness_N_per_m) {
    if (requested != Scheme::Auto) return requested;
    return stableTimeStep(model, Scheme::RungeKutta4, extra_stiffness_N_per_m) >= dt_s ? Scheme::RungeKutta4
                                                                                       : Scheme::BackwardEuler;
}

std::string tooManySubsteps(Scheme scheme, int substeps, double stableStep_s, double dt_s) {
    if (substeps <= kMaxSubsteps) return {};
    return std::string(schemeName(scheme)) + " would need " + std::to_string(substeps) + " substeps per " +
           formatDouble(dt_s * 1e3) + " ms step on this model (stable below " + threeDigits(stableStep_s * 1e6) +
           " us), more than the " + std::to_string(kMaxSubsteps) +
           " allowed: the implicit integrator (--integrator implicit, or auto) takes one solve per step";
}

}  // namespace hapticut::physics
