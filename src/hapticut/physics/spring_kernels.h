// The structural springs' forces and their Jacobians as SIMD kernels (Google Highway, chosen when the
// program starts, like the implicit solve's kernels): the explicit integrators' inner loop and the
// implicit step's assembly.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hapticut/physics/force_row.h"
#include "hapticut/physics/solver_kernels.h"

namespace hapticut::physics::kernels {

/// The springs' arrays as the kernel reads them (Springs in mass_spring_model.h).
struct SpringArrays {
    const std::uint32_t* a = nullptr;
    const std::uint32_t* b = nullptr;
    const double* restLength = nullptr;
    const double* stiffness = nullptr;
    const double* damping = nullptr;
};

/// f += the forces of springs [0, count) (spring_forces.h's formula; coincident ends give none), with x
/// and v three doubles a node and f a row a node. Each spring's force is the one the scalar formula
/// gives to the bit, and the forces reach f in the springs' order, so results do not depend on the
/// instruction set.
void addSpringForces(const SpringArrays& springs, std::size_t count, const double* x, const double* v, ForceRow* f);

/// The same for the springs listed in `list` (an active region's).
void addListedSpringForces(const SpringArrays& springs, const std::uint32_t* list, std::size_t count, const double* x,
                           const double* v, ForceRow* f);

/// The force on `node` of the springs listed in `list[0..count)`, each an end of it, by the scalar formula
/// (coincident ends give none), summed in the list's order into f[0..3).
void addSpringForcesOn(const SpringArrays& springs, std::uint32_t node, const std::uint32_t* list, std::size_t count,
                       const double* x, const double* v, double* f);

/// The implicit step's terms of a chunk of springs (backward_euler_system.h): whether the ends are
/// apart (the rest is undefined where they are not), the spring's part of the right-hand side on its
/// end a, h f + h² K dv (the second term only for a step's first linearisation), and its block
/// c0 I + u uᵀ = h² K + h D.
struct SpringJacobians {
    static constexpr std::size_t kSprings = 256;
    alignas(64) double bx[kSprings], by[kSprings], bz[kSprings];
    alignas(64) double c0[kSprings], ux[kSprings], uy[kSprings], uz[kSprings];
    bool apart[kSprings];
};

/// The terms of the springs listed in `list[0..count)`, count at most SpringJacobians::kSprings, for a
/// step of h seconds; `firstLinearisation` adds h² K dv to the right-hand side.
void springJacobians(const SpringArrays& springs, const std::uint32_t* list, std::size_t count, const double* x,
                     const double* v, double h, bool firstLinearisation, SpringJacobians& out);

/// The block-Jacobi preconditioner of the range's rows of a system: each row's block, diagonal I
/// plus its block to resting neighbours plus Σ_j (c0 I + u uᵀ) over its slots (padding slots add
/// nothing), as the product reads them, summed in double in that order and inverted by its cofactors,
/// into `inverse` in single precision. A row whose diagonal is zero (pinned, or padding) gets a zero block.
void invertRowBlocks(const SystemRows& rows, SymmetricBlocks& inverse, RowRange range);
inline void invertRowBlocks(const SystemRows& rows, SymmetricBlocks& inverse) {
    invertRowBlocks(rows, inverse, {0, rows.rows});
}

}  // namespace hapticut::physics::kernels
