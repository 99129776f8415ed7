// Scheme names.
#include "hapticut/physics/scheme.h"

namespace hapticut::physics {

std::string_view schemeName(Scheme scheme) {
    switch (scheme) {
        case Scheme::ExplicitEuler: return "euler";
        case Scheme::Midpoint: return "midpoint";
        case Scheme::RungeKutta4: return "rk4";
        case Scheme::SymplecticEuler: return "symplectic";
        case Scheme::BackwardEuler: return "implicit";
        case Scheme::Auto: return "auto";
    }
    return "?";
}

std::optional<Scheme> parseScheme(std::string_view name) {
    for (Scheme s : {Scheme::ExplicitEuler, Scheme::Midpoint, Scheme::RungeKutta4, Scheme::SymplecticEuler,
                     Scheme::BackwardEuler, Scheme::Auto})
        if (schemeName(s) == name) return s;
    return std::nullopt;
}

}  // namespace hapticut::physics
