// The integration schemes a Stepper offers (SPEC R5), by name for command lines and scene files.
#pragma once

#include <optional>
#include <string_view>

namespace hapticut::physics {

enum class Scheme { ExplicitEuler, Midpoint, RungeKutta4, SymplecticEuler };

std::string_view schemeName(Scheme scheme);  // "euler", "midpoint", "rk4", "symplectic"
std::optional<Scheme> parseScheme(std::string_view name);

}  // namespace hapticut::physics
