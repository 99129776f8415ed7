// How large a time step each scheme can take on a model: a per-node linear stability analysis of its
// local modes (DESIGN "Materials and stability").
#pragma once

#include <string>

#include "hapticut/physics/mass_spring_model.h"
#include "hapticut/physics/scheme.h"

namespace hapticut::physics {

/// Stable steps are taken this far below the analysed limit: the local modes only approximate the
/// model's, which couple nodes.
inline constexpr double kStableSafety = 0.9;

/// Whether the damped oscillator x'' = -w2 x - c x' (w2 in 1/s², c in 1/s) is stable under `scheme` with step h_s.
bool modeStable(Scheme scheme, double w2, double c, double h_s);

/// The largest step (s) for which that oscillator is stable; 1e9 when it has neither stiffness nor damping.
double largestStableStep(Scheme scheme, double w2, double c);

/// Lowers dt_s to what one node's modes allow: its positioning mode, and its highest mode against its
/// neighbours (springs at the node summing to k and d, so 2·Σk/m as in a chain). A node without mass
/// (inverse mass 0) is fixed and allows any step.
void lowerStableStepForNode(Scheme scheme, double& dt_s, double inverse_mass, double anchor_k, double anchor_d,
                            double k, double d);

/// Largest time step (s) for which every node's local modes are stable under `scheme`, with the
/// kStableSafety factor applied; 1e9 s for BackwardEuler, which is stable at any step.
/// `extra_stiffness_N_per_m` is added to every node, for a tool spring that may attach anywhere.
double stableTimeStep(const MassSpringModel& model, Scheme scheme, double extra_stiffness_N_per_m = 0);

/// The scheme to step `model` with at dt_s: `requested` itself unless it is Auto, which keeps the
/// thesis's RK4 where one RK4 step of dt_s is stable and takes BackwardEuler where RK4 would need substeps.
Scheme resolveScheme(Scheme requested, const MassSpringModel& model, double dt_s, double extra_stiffness_N_per_m = 0);

/// Substeps per step above which a run is refused instead of left to crawl: an explicit scheme this far
/// past its stable step spends minutes of wall clock per simulated second, where the implicit one takes
/// one solve a step.
inline constexpr int kMaxSubsteps = 10'000;

/// Why stepping with `scheme` at dt_s would need more than kMaxSubsteps substeps of `stableStep_s`, in
/// words a user can act on; empty when it would not.
std::string tooManySubsteps(Scheme scheme, int substeps, double stableStep_s, double dt_s);

}  // namespace hapticut::physics
