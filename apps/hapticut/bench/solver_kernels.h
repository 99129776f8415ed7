// The physics' SIMD kernels (the implicit solve's matrix product, its passes and its assembly, the
// explicit schemes' spring forces) under every instruction set this machine runs, in one run, so that
// their gain is measured against the portable code on the same machine and moment.
#pragma once

#include <string>
#include <vector>

#include "hapticut/physics/mass_spring_model.h"

namespace hapticut::bench {

struct KernelTiming {
    std::string target;           // "AVX3", "AVX2", "SSE4", "EMU128", ...
    double product_us = 0;        // median time of one product with the whole model's matrix
    double ns_per_coupling = 0;   // per spring end: each spring is read from both of its rows
    double cg_passes_us = 0;      // median times of a CG iteration's update pass and direction pass, added
    double cg_iteration_us = 0;   // the product and the passes: one block-Jacobi CG iteration
    double spring_forces_us = 0;  // median time of every spring's force added to the nodes
    double ns_per_spring = 0;
    double assembly_us = 0;  // median time of the implicit step's assembly of the whole model, laid out afresh
    double assembly_ns_per_spring = 0;
    double kept_layout_assembly_us = 0;  // the same over the last step's layout (SolveRegion::layout)
    double kept_layout_assembly_ns_per_spring = 0;
};

/// Times the product, the CG's passes and the assembly on `model` (all nodes unknowns, a 1 ms step)
/// and the spring forces (every node moved and moving a little) for at least `seconds` each per target.
std::vector<KernelTiming> timeSolverKernels(const physics::MassSpringModel& model, double seconds);

}  // namespace hapticut::bench
