// The integration schemes a Stepper offers (SPEC R5), by name for command lines and scene files.
#pragma once

#include <optional>
#include <string_view>

namespace hapticut::physics {

/// BackwardEuler is implicit (backward_euler.h); the rest are explicit. Auto is a request, not a scheme:
/// resolveScheme (stability.h) turns it into RK4 where that is stable at the step asked for, and into
/// BackwardEuler where it is not.
enum class Scheme { ExplicitEuler, Midpoint, RungeKutta4, SymplecticEuler, BackwardEuler, Auto };

/// "euler", "midpoint", "rk4", "symplectic", "implicit", "auto"
std::string_view schemeName(Scheme scheme);
std::optional<Scheme> parseScheme(std::string_view name);

}  // namespace hapticut::physics
