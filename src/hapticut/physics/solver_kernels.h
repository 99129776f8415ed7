// The implicit solve's inner loops as SIMD kernels (Google Highway), compiled for every instruction set
// Highway knows on this architecture and chosen when the program starts: one binary uses AVX-512 where
// the machine has it and SSE4 where it has nothing better.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hapticut::physics::kernels {

/// Rows are kept in slices of this many (a multiple of every target's double lanes); vectors are
/// padded to a whole number of slices with zero rows.
inline constexpr std::size_t kSliceRows = 16;

/// Three coordinate arrays of a field of 3-vectors, one entry per row (structure of arrays).
struct Field {
    std::vector<double> x, y, z;
    void resize(std::size_t rows) { x.resize(rows), y.resize(rows), z.resize(rows); }
};

/// A symmetric 3×3 block per row, one array per entry.
struct SymmetricBlocks {
    std::vector<float> xx, xy, xz, yy, yz, zz;
    void resize(std::size_t rows) {
        for (auto* a : {&xx, &xy, &xz, &yy, &yz, &zz}) a->resize(rows);
    }
};

/// The matrix c0 I + u uᵀ of each coupling between two rows, stored column by column within each
/// slice of kSliceRows rows (the sliced ELLPACK layout, SELL-16): slot (j, lane) of slice s is at
/// sliceBegin[s] + j·kSliceRows + lane, and a row with fewer couplings than the slice's widest is
/// padded with zero couplings to itself.
struct SlicedCouplings {
    std::vector<std::uint32_t> sliceBegin;  // one per slice, and the end
    std::vector<std::int32_t> other;        // the row at the coupling's other end
    std::vector<float> c0, ux, uy, uz;
};

/// The system's rows: a diagonal term, a symmetric block (springs to resting neighbours) and the
/// couplings to other rows.
struct SystemRows {
    std::size_t rows = 0;  // a multiple of kSliceRows
    const double* diagonal = nullptr;
    const SymmetricBlocks* toResting = nullptr;
    const SlicedCouplings* couplings = nullptr;
    /// False when every block to resting neighbours is zero (the whole organ awake): the product then
    /// leaves them unread, 24 of the 230 bytes a row it streams.
    bool anyResting = true;
};

/// A coarse level of the multilevel preconditioner by rows: a symmetric block on each row's diagonal and
/// one for each coupling to another row, the couplings in the sliced layout of SlicedCouplings (padding
/// slots are zero blocks to the row itself).
struct SlicedBlocks {
    std::vector<std::uint32_t> sliceBegin;  // one per slice, and the end
    std::vector<std::int32_t> other;        // the row at the coupling's other end
    SymmetricBlocks blocks;                 // by slot
};
struct BlockRows {
    std::size_t rows = 0;  // a multiple of kSliceRows
    const SymmetricBlocks* diagonal = nullptr;
    const SlicedBlocks* couplings = nullptr;
};

/// The rows a thread takes at a time when a solve's passes are shared out (a multiple of kSliceRows).
/// Fixed, so that the partial sums, and with them every result, do not depend on the number of threads.
inline constexpr std::size_t kChunkRows = 2048;

/// Rows first .. end - 1 of a system, both multiples of kSliceRows (end may be the padded row count).
/// The solve runs each pass over chunks of rows on several threads (worker_pool.h).
struct RowRange {
    std::size_t first = 0, end = 0;
};

/// The chunks of kChunkRows that make up `rows` rows (the last one short), and chunk `chunk`'s rows.
inline std::size_t chunksOf(std::size_t rows) { return (rows + kChunkRows - 1) / kChunkRows; }
inline RowRange chunkRows(std::size_t chunk, std::size_t rows) {
    return {chunk * kChunkRows, std::min(rows, (chunk + 1) * kChunkRows)};
}

/// Rows of out = A y; returns their part of yᵀ A y.
double multiply(const SystemRows& a, const Field& y, Field& out, RowRange range);
inline double multiply(const SystemRows& a, const Field& y, Field& out) { return multiply(a, y, out, {0, a.rows}); }

/// Rows of out = A y, or of out = b - A y (a residual) when b is given, for a coarse level's matrix. Each
/// row's sum builds up in registers, its couplings in slot order.
void blockProduct(const BlockRows& a, const Field& y, const Field* b, Field& out, RowRange range);

/// The sums a conjugate-gradient pass returns: |r|² and r·z, and the largest |r_i|² of a row.
struct Sums {
    double r2 = 0, rz = 0, rowMax2 = 0;
};

/// The first pass: r = b - Ax (`product` holds Ax), z = omega P⁻¹ r, p = z; the sums over the range's rows.
/// omega is 1 for block-Jacobi; the multilevel cycle's first smoothing is this pass's z with its weight.
Sums startPass(RowRange range, const Field& b, const Field& product, const SymmetricBlocks& inverse, Field& r, Field& z,
               Field& p, double omega = 1.0);
/// After a product q = A p: x += alpha p, r -= alpha q, z = omega P⁻¹ r.
Sums updatePass(RowRange range, double alpha, const Field& p, const Field& q, const SymmetricBlocks& inverse, Field& x,
                Field& r, Field& z, double omega = 1.0);
/// p = z + beta p.
void directionPass(RowRange range, double beta, const Field& z, Field& p);
/// Damped block-Jacobi smoothing for the multilevel preconditioner: z = omega P⁻¹ r with `product` null,
/// else z += omega P⁻¹ (r - product) where product holds A z; the sums over r and the new z.
Sums smoothPass(RowRange range, double omega, const Field& r, const Field* product, const SymmetricBlocks& inverse,
                Field& z);

/// The instruction set the kernels run with on this machine ("AVX3" is AVX-512, "EMU128" portable code).
const char* targetName();
/// Every instruction set compiled in that this machine runs, best first.
std::vector<const char*> supportedTargets();
/// Makes the kernels run with `name` (one of supportedTargets()); nullptr returns to the best. False
/// for a name that is not supported here. For benchmarks and tests comparing targets in one run.
bool forceTarget(const char* name);

}  // namespace hapticut::physics::kernels
