// An aggregation multigrid preconditioner for the backward-Euler system: the nodes are grouped into
// aggregates of a node and its neighbours (Vaněk, Mandel & Brezina 1996, "Algebraic multigrid by smoothed
// aggregation for second and fourth order elliptic problems", without the smoothing of the prolongation,
// as in Notay 2010, "An aggregation-based algebraic multigrid method"), level after level, and each level's
// matrix is the Galerkin product Pᵀ A P of the one above. A W-cycle with damped block-Jacobi smoothing
// then carries the residual's smooth part, which block-Jacobi alone moves by one ring of nodes per
// iteration, across the whole region at once. The coarse levels' products and smoothing run as SIMD
// kernels on single-precision blocks in the finest level's sliced layout (solver_kernels.h).
//
// Measured on the fully awake 1,000,000 heart at a 20 ms step (499,890 nodes, from a zero start to 1e-4):
// block-Jacobi took 156 conjugate-gradient iterations, this preconditioner 12; the 100,000 heart, 34 and 9.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "hapticut/common/worker_pool.h"
#include "hapticut/geometry/vec.h"
#include "hapticut/physics/solver_kernels.h"

namespace hapticut::physics {

/// A symmetric 3×3 block: xx, xy, xz, yy, yz, zz.
using SymmetricBlock = std::array<double, 6>;

class MultilevelPreconditioner {
public:
    MultilevelPreconditioner() = default;
    /// A copy starts empty, without levels or room: a copied vector keeps none of the room reserved, so
    /// its owner reserves again (as the stepper does when it is prepared) before the levels are laid out.
    MultilevelPreconditioner(const MultilevelPreconditioner&) {}
    MultilevelPreconditioner& operator=(const MultilevelPreconditioner& other) {
        if (this != &other) *this = MultilevelPreconditioner();
        return *this;
    }
    MultilevelPreconditioner(MultilevelPreconditioner&&) noexcept = default;
    MultilevelPreconditioner& operator=(MultilevelPreconditioner&&) noexcept = default;

    /// The most levels, the finest included.
    static constexpr std::size_t kMaxLevels = 8;
    /// A level with at most this many rows is solved exactly (a dense Cholesky factorisation).
    static constexpr std::size_t kDenseRows = 32;
    /// A level is made only where the aggregates shrink the rows this many times at least; else the
    /// level above is the coarsest, smoothed kCoarsestSweeps times.
    static constexpr std::size_t kMinimumCoarsening = 3;
    static constexpr int kCoarsestSweeps = 4;
    /// The smoothing's damping: block-Jacobi overshoots the highest modes undamped.
    static constexpr double kSmoothingWeight = 0.67;

    /// Room for the levels of a system of `nodes` unknowns with `slots` coupling slots (the sliced layout's,
    /// padding included), touched up front, so that laying out and assembling never allocate. The levels
    /// must be laid out again afterwards.
    void reserve(std::size_t nodes, std::size_t slots);
    /// Groups the rows of the laid-out system into aggregates, level by level, and works out where each
    /// entry of a level goes in the next. Run when the system's layout changes (BackwardEulerSystem::layOut).
    /// `count` is the system's unknowns (the rows past it are padding).
    void layOut(const kernels::SystemRows& fine, std::size_t count);
    /// The coarse levels' matrices from the assembled system: rows whose diagonal is zero (pinned nodes,
    /// padding) are left out of every level, as the solve leaves their unknowns at zero.
    void assemble(const kernels::SystemRows& fine);
    /// z = B r for the preconditioner B (symmetric and positive definite: the cycle's smoothing is the same
    /// before and after its coarse correction); returns the sums over r and z (kernels::Sums).
    /// With `smoothed`, z already holds the first smoothing, firstWeight() P⁻¹ r: the conjugate-gradient
    /// pass that updated r wrote it, which saves a pass over the rows.
    kernels::Sums apply(const kernels::SystemRows& fine, const kernels::SymmetricBlocks& inverse,
                        const kernels::Field& r, kernels::Field& z, OwnedWorkerPool& pool, bool smoothed = false);
    /// The weight of the first smoothing, z = ω P⁻¹ r (1 without a coarse level: plain block-Jacobi).
    double firstWeight() const { return coarse_.empty() ? 1.0 : kSmoothingWeight; }

    /// Whether the levels are laid out (layOut since the last reserve or copy).
    bool laidOut() const { return laidOut_; }
    /// The levels laid out, the finest included (1: no coarse level, plain block-Jacobi smoothing).
    std::size_t levels() const { return 1 + coarse_.size(); }
    /// The rows of level `level` (0: the finest).
    std::size_t rowsOf(std::size_t level) const { return level == 0 ? count_ : coarse_[level - 1].rows; }

private:
    static constexpr std::uint32_t kNone = ~std::uint32_t{0};
    static constexpr std::uint32_t kToDiagonal = ~std::uint32_t{0} - 1;

    /// A coarse level: its matrix by block rows (a diagonal block and off-diagonal entries, both
    /// symmetric), how it aggregates the level above, and its vectors.
    struct Level {
        std::size_t rows = 0;
        std::vector<SymmetricBlock> diagonal;         // by row, summed in double for the next level
        std::vector<std::uint32_t> rowStart, column;  // the off-diagonal entries of row r: rowStart[r] ..
        std::vector<SymmetricBlock> offDiagonal;
        // The matrix as the cycle's SIMD kernels read it (solver_kernels.h), in single precision like the
        // finest level's couplings: rows padded to whole slices, each entry at its slot (slotOf).
        kernels::SymmetricBlocks diagonalBlocks, inverseBlocks;  // the inverse is zero for an empty row
        kernels::SlicedBlocks couplings;
        std::vector<std::uint32_t> slotOf;
        // The rows of the level above in each of this level's rows, and where each entry of the level
        // above goes here: kToDiagonal (its row's and column's aggregates are the same), an entry's index,
        // or kNone (an empty slot).
        std::vector<std::uint32_t> childStart, children, target;
        std::vector<std::uint32_t> aggregateOf;  // by row of the level above: its row here, or kNone
        kernels::Field r, e, t, held;  // residual, correction, scratch, the W-cycle's first correction; padded
        std::size_t rowCapacity = 0, entryCapacity = 0;

        std::size_t paddedRows() const {
            return (rows + kernels::kSliceRows - 1) / kernels::kSliceRows * kernels::kSliceRows;
        }
        kernels::BlockRows matrix() const { return {paddedRows(), &diagonalBlocks, &couplings}; }
    };

    /// Aggregates the rows of a level whose neighbours `neighbours(row, visit)` lists into `next`;
    /// false when they do not shrink by kMinimumCoarsening or do not fit the room reserved.
    template <class Neighbours>
    bool aggregate(std::size_t rows, Neighbours&& neighbours, Level& next);
    /// Lays a level's entries out in slices for the kernels; false when they do not fit the room reserved.
    static bool sliceEntries(Level& level);
    /// Copies a level's assembled blocks, and its diagonal's inverses, into the kernels' layout.
    static void publishBlocks(Level& level);
    /// Moves the levels in use back to the spares.
    void release();
    /// The W-cycle's coarse correction at coarse_[index]: two cycles, the second on the residual the first
    /// left (one exact solve at a factorised coarsest level), into that level's e.
    void twoCycles(std::size_t index);
    /// The cycle at coarse_[index] (level index + 1): e = B r on that level's vectors.
    void cycle(std::size_t index);
    /// out = r - A e at a coarse level.
    static void residual(const Level& level, const kernels::Field& e, kernels::Field& out);
    /// e = e + ω D⁻¹ (r - A e) at a coarse level, or e = ω D⁻¹ r when `fromZero`.
    static void smooth(Level& level, bool fromZero);
    /// The coarsest level's exact solve.
    void solveCoarsest(Level& level);

    std::size_t count_ = 0;
    bool laidOut_ = false;
    std::vector<Level> coarse_;           // levels 1 .. in use; capacity for kMaxLevels - 1, reserved
    std::vector<Level> spare_;            // the levels' reserved room while not in use (layOut moves them in and out)
    std::vector<std::uint8_t> excluded_;  // by fine row, while assembling: left out (a zero diagonal)
    std::vector<std::uint32_t> stamp_, mark_;  // by row, while laying out a level's entries
    kernels::Field product_;                   // the finest level's A z
    std::vector<kernels::Sums> partial_;       // by chunk of fine rows
    // The coarsest level's matrix when it is small, factorised at each assembly; in fixed room (no allocation).
    using DenseMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3 * kDenseRows, 3 * kDenseRows>;
    using DenseVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3 * kDenseRows, 1>;
    Eigen::LLT<DenseMatrix> factor_;
    bool dense_ = false;  // the coarsest level is solved by factor_
};

}  // namespace hapticut::physics
