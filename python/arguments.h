// Arguments the Python functions share, checked as the command line checks them.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "hapticut/physics/scheme.h"

namespace hapticut::python {

/// The integrator a script names, or ValueError listing the names.
inline physics::Scheme schemeArgument(const std::string& name) {
    const auto scheme = physics::parseScheme(name);
    if (!scheme)
        throw pybind11::value_error("integrator: '" + name +
                                    "' is none of auto, euler, midpoint, rk4, symplectic, implicit");
    return *scheme;
}

}  // namespace hapticut::python
