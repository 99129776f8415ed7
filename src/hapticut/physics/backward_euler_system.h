// The linear system of one linearised backward-Euler step (Baraff & Witkin 1998, "Large steps in cloth
// simulation"), assembled without forming a matrix: (M - h D - h² K) Δv = h (f(x0, v0) + h K v0), where
// K = ∂f/∂x and D = ∂f/∂v of the springs, the positioning springs and the tools' coupling; and the
// same matrix with a Newton correction's right-hand side, h f(x, v) - M (v - v0), for the steps where
// one linearisation is not enough.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/common/worker_pool.h"
#include "hapticut/geometry/vec.h"
#include "hapticut/physics/mass_spring_model.h"
#include "hapticut/physics/solver_kernels.h"
#include "hapticut/physics/spring_kernels.h"

namespace hapticut::physics {

/// The nodes a step solves for and the springs that act on them. `touched` holds `nodes` and the
/// resting neighbours the springs also reach; those stay where they are (their Δv is zero).
struct SolveRegion {
    std::span<const std::uint32_t> nodes, touched, springs;
    /// A number that changes whenever the lists or the listed springs' ends may have changed; 0 when
    /// unknown. Steps over the same layout reuse where each spring's terms go in the matrix.
    std::uint64_t layout = 0;
};

/// The unknowns are numbered by their place in the region's node list, so that every vector of the
/// solve is contiguous whatever part of the organ is awake.
///
/// Each spring contributes h² K_s + h D_s = c0 I + u uᵀ to the matrix (c0 >= 0), so it is kept as four
/// numbers. K_s = k [α I + (1 - α) n nᵀ] with α = max(0, 1 - r/l): a compressed spring's transverse
/// stiffness, negative in the exact Jacobian, is dropped so the matrix stays positive definite (Choi &
/// Ko 2002). D_s = k_d n nᵀ; the damping force's change with direction is left out, as in Baraff-Witkin.
/// A spring to a resting neighbour only adds to its awake end's diagonal block (the neighbour's Δv is
/// zero). The tool's coupling is lumped onto the touched triangle's corners by their reaction weights:
/// the exact Jacobian (reaction weights times barycentric ones) is not symmetric; the lumped one keeps
/// each corner's row sum, which is what a press of the whole triangle feels.
class BackwardEulerSystem {
public:
    /// Capacity for `nodes` and `springs`, touched up front.
    void reserve(std::size_t nodes, std::size_t springs);
    /// Room for a model of `nodes` nodes.
    void resize(std::size_t nodes);

    /// Builds the matrix, the right-hand side and the block-Jacobi preconditioner for a step of h seconds
    /// from the model's current state, over `region`. With `startVelocity` (by unknown) the state is a
    /// Newton iterate x = x0 + h v of a step that started at those velocities, and the right-hand side
    /// is the correction's; without it, the step's first linearisation.
    /// With `pool`, chunks of kernels::kChunkRows rows, and the springs within them, are assembled on its
    /// threads; the result is the same, to the bit, with any number of threads.
    void assemble(const MassSpringModel& model, double h, SolveRegion region, std::span<const Vec3> startVelocity = {},
                  OwnedWorkerPool* pool = nullptr);
    /// Whether a motion m by unknown (zero on resting neighbours) moves some spring's ends apart by more
    /// than `fraction` of its rest length, |m_b - m_a| > fraction · rest length; springs shorter than a
    /// nanometre are skipped. It stops at the first: its caller asks no more, and the largest motion cost a
    /// division and a dependent maximum a spring. `region` is the one the last assemble() laid out.
    bool movesApartMoreThan(const Springs& springs, SolveRegion region, std::span<const Vec3> motion, double fraction,
                            OwnedWorkerPool* pool = nullptr) const;

    /// The number of unknowns (3-vectors): the region's nodes.
    std::size_t size() const { return count_; }
    /// The rows of the kernels' vectors: size() padded to whole slices (the padding rows are zero).
    std::size_t rows() const { return rows_; }
    kernels::SystemRows matrix() const {
        return {rows_, diagonal_.data(), &toResting_, &sliced_, !restingSum_.empty()};
    }
    const kernels::SymmetricBlocks& inverseBlocks() const { return inverseBlock_; }
    const kernels::Field& rhs() const { return rhs_; }
    /// How many times the rows have been laid out afresh: a preconditioner built on the layout checks it.
    std::uint64_t layoutsMade() const { return layoutsMade_; }
    /// The coupling slots the layout can hold (padding included), for a preconditioner's room.
    std::size_t slotCapacity() const { return sliced_.other.capacity(); }

private:
    static constexpr std::uint32_t kResting = ~std::uint32_t{0};

    static void setBlock(kernels::SymmetricBlocks& blocks, std::size_t k, const Mat3& m);
    /// Works out where each of the region's springs writes its terms (endA_ .. slotB_) and lays the
    /// rows out slice by slice for the kernels, every slot a zero coupling of its row to itself until
    /// a spring writes it. Needs unknownOf_, count_ and rows_ for the region.
    void layOut(const Springs& springs, SolveRegion region);
    /// Whether the kept layout is the one `region` would be given (checked where assertions are on).
    bool layoutMatches(const Springs& springs, SolveRegion region) const;
    /// The terms of the laid-out springs first .. end - 1 (in bucket order), with `chunk` for scratch.
    void assembleSprings(const MassSpringModel& model, double h, bool firstLinearisation, std::size_t first,
                         std::size_t end, kernels::SpringJacobians& chunk);
    /// The chunks of kernels::kChunkRows rows, the last padded; one (empty) when there are no rows.
    std::size_t rowChunks() const { return std::max<std::size_t>(1, kernels::chunksOf(rows_)); }

    std::vector<std::uint32_t> unknownOf_;  // by node: its unknown, or kResting; valid on the region's touched nodes
    std::size_t count_ = 0, rows_ = 0;
    // By unknown. The matrix is kept by rows, each with its springs to other unknowns, so that a product
    // gathers and never scatters: every row is summed in registers and written once.
    std::vector<double> diagonal_;         // m + h d + h² k of its own terms and the tool's
    kernels::SymmetricBlocks toResting_;   // its springs to resting neighbours, whose Δv is zero
    std::vector<std::uint32_t> rowStart_;  // it has rowStart_[k + 1] - rowStart_[k] couplings
    // A spring's c0 I + u uᵀ, once in each end's row, laid out for the kernels. The matrix is kept in
    // single precision: it halves the memory each iteration streams through, and the solution is still
    // the double-precision right-hand side's (a rounded matrix changes the path of the iterations, not
    // where a converged solve ends up).
    kernels::SlicedCouplings sliced_;
    // The region's springs in buckets (layOut): one per chunk of rows, for the springs whose awake ends
    // all lie in it; one per boundary between neighbouring chunks; and a last for the springs that reach
    // further. The chunks' buckets are assembled in parallel, then the even boundaries', then the odd
    // ones' (no two write the same row), then the last on the calling thread. Nodes in vertex order keep
    // almost every spring in the first two kinds. ordered_ lists the springs bucket by bucket, each in
    // the list's order, and position_ gives each listed spring's place in it.
    std::vector<std::uint32_t> bucketStart_, ordered_, position_;
    // By place in ordered_: the unknowns at the ends (kResting for a resting neighbour) and, for a spring
    // between two unknowns, its slot in end a's row and in end b's. They depend only on the region's lists
    // and the springs' ends: laying them out was a third of an assembly, so steps over the same layout
    // (region.layout) reuse them and write the slots in place.
    std::uint64_t layout_ = 0;  // the region.layout they were laid out for; 0: none
    std::uint64_t layoutsMade_ = 0;
    std::vector<std::uint32_t> endA_, endB_, slotA_, slotB_;
    std::vector<std::uint32_t> column_;      // by unknown, while laying out: its row's next free column
    kernels::SymmetricBlocks inverseBlock_;  // the preconditioner
    // Its springs' blocks to resting neighbours, while assembling: few rows have any (the edge of an awake
    // region), so each such row has one block in restingSum_, at restingOf_[k], given at layout.
    static constexpr std::uint32_t kNoResting = ~std::uint32_t{0};
    std::vector<std::uint32_t> restingOf_;
    std::vector<Mat3> restingSum_;
    kernels::Field rhs_;
    std::vector<kernels::SpringJacobians> scratch_;  // by thread: the springs' terms, a chunk at a time
};

}  // namespace hapticut::physics
