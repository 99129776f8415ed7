// The linear system of one linearised backward-Euler step (Baraff & Witkin 1998, "Large steps in cloth
// simulation"), assembled without forming a matrix: (M - h D - h² K) Δv = h (f(x0, v0) + h K v0), where
// K = ∂f/∂x and D = ∂f/∂v of the springs, the positioning springs and the tools' coupling.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/geometry/vec.h"
#include "hapticut/physics/mass_spring_model.h"

namespace hapticut::physics {

/// The nodes a step solves for and the springs that act on them. `touched` holds `nodes` and the
/// resting neighbours the springs also reach; those stay where they are (their Δv is zero).
struct SolveRegion {
    std::span<const std::uint32_t> nodes, touched, springs;
};

/// Each spring contributes h² K_s + h D_s = c0 I + u uᵀ to the matrix (c0 >= 0), so it is kept as four
/// numbers. K_s = k [α I + (1 - α) n nᵀ] with α = max(0, 1 - r/l): a compressed spring's transverse
/// stiffness, negative in the exact Jacobian, is dropped so the matrix stays positive definite (Choi &
/// Ko 2002). D_s = k_d n nᵀ; the damping force's change with direction is left out, as in Baraff-Witkin.
/// The tool's coupling is lumped onto the touched triangle's corners by their reaction weights: the
/// exact Jacobian (reaction weights times barycentric ones) is not symmetric, the lumped one keeps each
/// corner's row sum, which is what a press of the whole triangle feels.
class BackwardEulerSystem {
public:
    /// Capacity for `nodes` and `springs`, touched up front; then sized to at least the given counts.
    void reserve(std::size_t nodes, std::size_t springs);
    void resize(std::size_t nodes, std::size_t springs);

    /// Builds the matrix, the right-hand side and the block-Jacobi preconditioner for a step of h seconds
    /// from the model's current state, over `region`. The model's springs must not change until the
    /// products that follow are done.
    void assemble(const MassSpringModel& model, double h, SolveRegion region);

    /// out = A y on the region's nodes. y must be zero on the resting neighbours.
    void multiply(std::span<const Vec3> y, std::span<Vec3> out) const;
    /// z = P⁻¹ r with P the 3×3 diagonal blocks of A.
    void precondition(std::span<const Vec3> r, std::span<Vec3> z) const;
    std::span<const Vec3> rhs() const { return rhs_; }
    const SolveRegion& region() const { return region_; }

private:
    SolveRegion region_;
    const Springs* springs_ = nullptr;  // the assembled model's, for the ends in products
    std::vector<double> nodeDiagonal_;  // m + h d + h² k of the node's own terms; zero on resting neighbours
    std::vector<Mat3> inverseBlock_;    // the preconditioner; zero for a node without inverse mass
    std::vector<double> springScalar_;  // c0
    std::vector<Vec3> springAxis_;      // u
    std::vector<Vec3> rhs_;
    std::vector<std::uint32_t> pinned_;  // region nodes without inverse mass: their rows are left out
};

}  // namespace hapticut::physics
