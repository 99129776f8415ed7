// The structural springs' forces as a SIMD kernel (Google Highway, chosen when the program starts, like
// the implicit solve's kernels): the explicit integrators' inner loop.
#pragma once

#include <cstddef>
#include <cstdint>

namespace hapticut::physics::kernels {

/// The springs' arrays as the kernel reads them (Springs in mass_spring_model.h).
struct SpringArrays {
    const std::uint32_t* a = nullptr;
    const std::uint32_t* b = nullptr;
    const double* restLength = nullptr;
    const double* stiffness = nullptr;
    const double* damping = nullptr;
};

/// f += the forces of springs [0, count) (spring_forces.h's formula; coincident ends give none), with x,
/// v and f three doubles for each of `nodes` nodes. Each spring's force is the one the scalar formula
/// gives to the bit, and the forces reach f in the springs' order, so results do not depend on the
/// instruction set.
void addSpringForces(const SpringArrays& springs, std::size_t count, std::size_t nodes, const double* x,
                     const double* v, double* f);

/// The same for the springs listed in `list` (an active region's).
void addListedSpringForces(const SpringArrays& springs, const std::uint32_t* list, std::size_t count, std::size_t nodes,
                           const double* x, const double* v, double* f);

}  // namespace hapticut::physics::kernels
