// The implicit solve's matrix product under every instruction set this machine runs, in one run, so
// that the SIMD kernels' gain is measured against the portable code on the same machine and moment.
#pragma once

#include <string>
#include <vector>

#include "hapticut/physics/mass_spring_model.h"

namespace hapticut::bench {

struct KernelTiming {
    std::string target;          // "AVX3", "AVX2", "SSE4", "EMU128", ...
    double product_us = 0;       // median time of one product with the whole model's matrix
    double ns_per_coupling = 0;  // per spring end: each spring is read from both of its rows
};

/// Times the product on `model` (all nodes unknowns, a 1 ms step) for at least `seconds` per target.
std::vector<KernelTiming> timeSolverKernels(const physics::MassSpringModel& model, double seconds);

}  // namespace hapticut::bench
