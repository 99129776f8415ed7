// The aggregates, the coarse levels' Galerkin matrices and the W-cycle of the multilevel preconditioner.
#include "hapticut/physics/multilevel_preconditioner.h"

#include <algorithm>

#include "hapticut/common/reserve.h"

namespace hapticut::physics {

namespace {

constexpr std::size_t kSlice = kernels::kSliceRows;

/// Adds s (c0 I + u uᵀ) to a block.
void addCoupling(SymmetricBlock& m, double s, double c0, double ux, double uy, double uz) {
    m[0] += s * (c0 + ux * ux), m[1] += s * ux * uy, m[2] += s * ux * uz;
    m[3] += s * (c0 + uy * uy), m[4] += s * uy * uz, m[5] += s * (c0 + uz * uz);
}

void add(SymmetricBlock& m, const SymmetricBlock& a) {
    for (std::size_t i = 0; i < 6; ++i) m[i] += a[i];
}

/// The inverse of a symmetric positive definite block by its adjugate; zero for a block that is not.
SymmetricBlock inverseOf(const SymmetricBlock& m) {
    const double a = m[3] * m[5] - m[4] * m[4], b = m[2] * m[4] - m[1] * m[5], c = m[1] * m[4] - m[2] * m[3];
    const double det = m[0] * a + m[1] * b + m[2] * c;
    if (!(det > 0) || !(m[0] > 0)) return {};
    const double s = 1 / det;
    return {s * a,
            s * b,
            s * c,
            s * (m[0] * m[5] - m[2] * m[2]),
            s * (m[1] * m[2] - m[0] * m[4]),
            s * (m[0] * m[3] - m[1] * m[1])};
}

/// Block `b` into slot `at` of the kernels' single-precision blocks.
void store(kernels::SymmetricBlocks& blocks, std::size_t at, const SymmetricBlock& b) {
    blocks.xx[at] = static_cast<float>(b[0]), blocks.xy[at] = static_cast<float>(b[1]);
    blocks.xz[at] = static_cast<float>(b[2]), blocks.yy[at] = static_cast<float>(b[3]);
    blocks.yz[at] = static_cast<float>(b[4]), blocks.zz[at] = static_cast<float>(b[5]);
}

void reserveBlocks(kernels::SymmetricBlocks& blocks, std::size_t n) {
    for (auto* a : {&blocks.xx, &blocks.xy, &blocks.xz, &blocks.yy, &blocks.yz, &blocks.zz}) reserveTouched(*a, n);
}

void reserveField(kernels::Field& f, std::size_t n) {
    for (auto* a : {&f.x, &f.y, &f.z}) reserveTouched(*a, n);
}

/// Sized to `n` rows, all zero: the padding rows stay so through the cycle.
void zeroed(kernels::Field& f, std::size_t n) {
    for (auto* a : {&f.x, &f.y, &f.z}) a->assign(n, 0.0);
}

/// The finest level's rows: each with the slots of its slice, whose `other` is itself on padding.
template <class Visit>
void visitFineNeighbours(const kernels::SlicedCouplings& c, std::uint32_t row, Visit&& visit) {
    const std::size_t begin = c.sliceBegin[row / kSlice], end = c.sliceBegin[row / kSlice + 1];
    for (std::size_t slot = begin + row % kSlice; slot < end; slot += kSlice)
        if (c.other[slot] != static_cast<std::int32_t>(row))
            visit(static_cast<std::uint32_t>(slot), static_cast<std::uint32_t>(c.other[slot]));
}

}  // namespace

void MultilevelPreconditioner::reserve(std::size_t nodes, std::size_t slots) {
    release();
    laidOut_ = false;
    reserveTouched(excluded_, nodes + kSlice);
    reserveTouched(stamp_, nodes);
    reserveTouched(mark_, nodes);
    for (auto* a : {&product_.x, &product_.y, &product_.z}) reserveTouched(*a, nodes + kSlice);
    reserveTouched(partial_, nodes / kernels::kChunkRows + 2);
    coarse_.reserve(kMaxLevels - 1);
    spare_.resize(kMaxLevels - 1);
    // Each level's room: a third of the rows above at most (kMinimumCoarsening), and on average 12 entries
    // a row (a surface's aggregates have 6 to 8 neighbouring ones), twice that in slices, whose rows are
    // padded to the slice's longest; a level that needs more is not made. Reserved in place, whatever
    // room a copy of this object kept (a copied vector keeps none).
    std::size_t above = nodes, aboveEntries = slots;
    for (Level& level : spare_) {
        level.rowCapacity = above / kMinimumCoarsening + 1;
        level.entryCapacity = 12 * level.rowCapacity;
        const std::size_t rows = level.rowCapacity, padded = rows + kSlice;
        reserveTouched(level.diagonal, rows);
        reserveBlocks(level.diagonalBlocks, padded);
        reserveBlocks(level.inverseBlocks, padded);
        reserveBlocks(level.couplings.blocks, 2 * level.entryCapacity);
        reserveTouched(level.couplings.other, 2 * level.entryCapacity);
        reserveTouched(level.couplings.sliceBegin, padded / kSlice + 1);
        reserveTouched(level.slotOf, level.entryCapacity);
        for (auto* f : {&level.r, &level.e, &level.t, &level.held}) reserveField(*f, padded);
        reserveTouched(level.rowStart, rows + 1);
        reserveTouched(level.childStart, rows + 1);
        reserveTouched(level.column, level.entryCapacity);
        reserveTouched(level.offDiagonal, level.entryCapacity);
        reserveTouched(level.children, above);
        reserveTouched(level.aggregateOf, above);
        reserveTouched(level.target, aboveEntries);
        above = rows, aboveEntries = level.entryCapacity;
    }
}

template <class Neighbours>
bool MultilevelPreconditioner::aggregate(std::size_t rows, Neighbours&& neighbours, Level& next) {
    std::vector<std::uint32_t>& aggregateOf = next.aggregateOf;
    if (rows > aggregateOf.capacity()) return false;
    aggregateOf.assign(rows, kNone);
    mark_.assign(rows, 0);  // 1: joined an aggregate in the second pass
    std::uint32_t count = 0;
    // First, every row whose neighbours are all free starts an aggregate with them.
    for (std::uint32_t i = 0; i < rows; ++i) {
        if (aggregateOf[i] != kNone) continue;
        bool free = true;
        neighbours(i, [&](std::uint32_t, std::uint32_t j) { free = free && aggregateOf[j] == kNone; });
        if (!free) continue;
        aggregateOf[i] = count;
        neighbours(i, [&](std::uint32_t, std::uint32_t j) { aggregateOf[j] = count; });
        ++count;
    }
    // Then the rows left over join a neighbouring aggregate of the first pass, and the few left after
    // that start aggregates of their own with their free neighbours.
    for (std::uint32_t i = 0; i < rows; ++i) {
        if (aggregateOf[i] != kNone) continue;
        neighbours(i, [&](std::uint32_t, std::uint32_t j) {
            if (aggregateOf[i] == kNone && aggregateOf[j] != kNone && !mark_[j]) aggregateOf[i] = aggregateOf[j];
        });
        if (aggregateOf[i] != kNone) mark_[i] = 1;
    }
    for (std::uint32_t i = 0; i < rows; ++i) {
        if (aggregateOf[i] != kNone) continue;
        aggregateOf[i] = count;
        neighbours(i, [&](std::uint32_t, std::uint32_t j) {
            if (aggregateOf[j] == kNone) aggregateOf[j] = count;
        });
        ++count;
    }
    if (count * kMinimumCoarsening > rows || count > next.rowCapacity) return false;
    next.rows = count;
    // The rows in each aggregate, in order (a counting sort).
    next.childStart.assign(count + 1, 0);
    for (std::uint32_t i = 0; i < rows; ++i) ++next.childStart[aggregateOf[i] + 1];
    for (std::size_t a = 0; a < count; ++a) next.childStart[a + 1] += next.childStart[a];
    next.children.resize(rows);
    stamp_.assign(count, 0);  // each aggregate's next place
    for (std::uint32_t i = 0; i < rows; ++i)
        next.children[next.childStart[aggregateOf[i]] + stamp_[aggregateOf[i]]++] = i;
    // Each aggregate's entries: one for every aggregate its rows reach, in the order first reached;
    // and where each entry of the level above goes.
    stamp_.assign(count, kNone);  // the aggregate that last reached it
    mark_.assign(count, 0);       // its entry there
    next.rowStart.assign(count + 1, 0);
    next.column.clear();
    bool fits = true;
    for (std::uint32_t a = 0; a < count && fits; ++a) {
        for (std::uint32_t c = next.childStart[a]; c < next.childStart[a + 1]; ++c)
            neighbours(next.children[c], [&](std::uint32_t entry, std::uint32_t j) {
                const std::uint32_t b = aggregateOf[j];
                if (b == a) {
                    next.target[entry] = kToDiagonal;
                    return;
                }
                if (stamp_[b] != a) {
                    if (next.column.size() == next.entryCapacity) {
                        fits = false;
                        return;
                    }
                    stamp_[b] = a, mark_[b] = static_cast<std::uint32_t>(next.column.size());
                    next.column.push_back(b);
                }
                next.target[entry] = mark_[b];
            });
        next.rowStart[a + 1] = static_cast<std::uint32_t>(next.column.size());
    }
    if (!fits) return false;
    next.offDiagonal.resize(next.column.size());
    next.diagonal.resize(count);
    for (auto* f : {&next.r, &next.e, &next.t, &next.held}) zeroed(*f, next.paddedRows());
    return sliceEntries(next);
}

bool MultilevelPreconditioner::sliceEntries(Level& level) {
    // Each slice as wide as its longest row; the shorter rows, and the padding rows past the last,
    // padded with zero blocks to themselves.
    const std::size_t padded = level.paddedRows(), slices = padded / kSlice;
    kernels::SlicedBlocks& c = level.couplings;
    auto length = [&](std::size_t row) { return row < level.rows ? level.rowStart[row + 1] - level.rowStart[row] : 0; };
    c.sliceBegin.assign(slices + 1, 0);
    for (std::size_t slice = 0; slice < slices; ++slice) {
        std::size_t width = 0;
        for (std::size_t row = slice * kSlice; row < (slice + 1) * kSlice; ++row)
            width = std::max<std::size_t>(width, length(row));
        c.sliceBegin[slice + 1] = static_cast<std::uint32_t>(c.sliceBegin[slice] + width * kSlice);
    }
    const std::size_t slots = c.sliceBegin[slices];
    if (slots > c.other.capacity()) return false;
    c.other.resize(slots);
    level.slotOf.resize(level.column.size());
    for (std::size_t slice = 0; slice < slices; ++slice)
        for (std::size_t row = slice * kSlice; row < (slice + 1) * kSlice; ++row)
            for (std::size_t j = 0, slot = c.sliceBegin[slice] + row % kSlice; slot < c.sliceBegin[slice + 1];
                 ++j, slot += kSlice) {
                if (j < length(row)) {
                    const std::uint32_t entry = level.rowStart[row] + static_cast<std::uint32_t>(j);
                    c.other[slot] = static_cast<std::int32_t>(level.column[entry]);
                    level.slotOf[entry] = static_cast<std::uint32_t>(slot);
                } else {
                    c.other[slot] = static_cast<std::int32_t>(row);
                }
            }
    kernels::SymmetricBlocks& m = c.blocks;
    for (auto* a : {&m.xx, &m.xy, &m.xz, &m.yy, &m.yz, &m.zz}) a->assign(slots, 0.0f);
    for (kernels::SymmetricBlocks* blocks : {&level.diagonalBlocks, &level.inverseBlocks})
        for (auto* a : {&blocks->xx, &blocks->xy, &blocks->xz, &blocks->yy, &blocks->yz, &blocks->zz})
            a->assign(padded, 0.0f);
    return true;
}

void MultilevelPreconditioner::publishBlocks(Level& level) {
    for (std::size_t a = 0; a < level.rows; ++a) {
        store(level.diagonalBlocks, a, level.diagonal[a]);
        store(level.inverseBlocks, a, inverseOf(level.diagonal[a]));
    }
    for (std::size_t e = 0; e < level.offDiagonal.size(); ++e)
        store(level.couplings.blocks, level.slotOf[e], level.offDiagonal[e]);
}

void MultilevelPreconditioner::release() {
    while (!coarse_.empty()) {  // back to the spares, whose room they are
        spare_[coarse_.size() - 1] = std::move(coarse_.back());
        coarse_.pop_back();
    }
}

void MultilevelPreconditioner::layOut(const kernels::SystemRows& fine, std::size_t count) {
    count_ = count;
    release();
    laidOut_ = true;
    const kernels::SlicedCouplings& c = *fine.couplings;
    std::size_t rows = count;
    while (coarse_.size() < spare_.size() && rows > kDenseRows) {
        Level& next = spare_[coarse_.size()];
        bool made = false;
        if (coarse_.empty()) {
            if (c.other.size() <= next.target.capacity()) {
                next.target.assign(c.other.size(), kNone);
                made = aggregate(
                    rows, [&](std::uint32_t i, auto&& visit) { visitFineNeighbours(c, i, visit); }, next);
            }
        } else {
            const Level& above = coarse_.back();
            next.target.assign(above.column.size(), kNone);
            made = aggregate(
                rows,
                [&](std::uint32_t i, auto&& visit) {
                    for (std::uint32_t e = above.rowStart[i]; e < above.rowStart[i + 1]; ++e) visit(e, above.column[e]);
                },
                next);
        }
        if (!made) break;
        coarse_.push_back(std::move(next));
        rows = coarse_.back().rows;
    }
}

void MultilevelPreconditioner::assemble(const kernels::SystemRows& fine) {
    if (coarse_.empty()) return;
    const kernels::SlicedCouplings& c = *fine.couplings;
    const kernels::SymmetricBlocks& resting = *fine.toResting;
    excluded_.resize(count_);
    for (std::size_t k = 0; k < count_; ++k) excluded_[k] = fine.diagonal[k] == 0;
    // Level 1 from the finest rows, slice by slice in the layout's own order, each row's terms summed in
    // registers: its diagonal block with its couplings, added to its aggregate's; and each coupling taken
    // off the entry where the other end's aggregate meets its own. A coupling within one aggregate adds
    // to its diagonal and takes off again, so it is left out. (Walked aggregate by aggregate instead, each
    // row's slots lie a slice's width apart, and this took four times as long.) On this thread, so that
    // the sums come in one order.
    Level& first = coarse_.front();
    std::fill(first.diagonal.begin(), first.diagonal.end(), SymmetricBlock{});
    std::fill(first.offDiagonal.begin(), first.offDiagonal.end(), SymmetricBlock{});
    for (std::size_t slice = 0; slice * kSlice < count_; ++slice) {
        const std::size_t begin = c.sliceBegin[slice], width = (c.sliceBegin[slice + 1] - begin) / kSlice;
        for (std::size_t row = slice * kSlice; row < std::min(count_, (slice + 1) * kSlice); ++row) {
            if (excluded_[row]) continue;  // a pinned node's row
            const double m = fine.diagonal[row];
            SymmetricBlock d{m + resting.xx[row], resting.xy[row], resting.xz[row],
                             m + resting.yy[row], resting.yz[row], m + resting.zz[row]};
            for (std::size_t j = 0, slot = begin + row % kSlice; j < width; ++j, slot += kSlice) {
                const auto other = static_cast<std::uint32_t>(c.other[slot]);
                const std::uint32_t t = first.target[slot];
                if (other == row || (t == kToDiagonal && !excluded_[other])) continue;
                const double c0 = c.c0[slot], ux = c.ux[slot], uy = c.uy[slot], uz = c.uz[slot];
                addCoupling(d, 1, c0, ux, uy, uz);  // the row's own term, whatever the other end
                if (!excluded_[other]) addCoupling(first.offDiagonal[t], -1, c0, ux, uy, uz);
            }
            add(first.diagonal[first.aggregateOf[row]], d);
        }
    }
    publishBlocks(first);
    // The coarser levels from the one above, on this thread: each is a few times smaller.
    for (std::size_t l = 1; l < coarse_.size(); ++l) {
        const Level& above = coarse_[l - 1];
        Level& level = coarse_[l];
        std::fill(level.offDiagonal.begin(), level.offDiagonal.end(), SymmetricBlock{});
        for (std::size_t a = 0; a < level.rows; ++a) {
            SymmetricBlock d{};
            for (std::uint32_t ch = level.childStart[a]; ch < level.childStart[a + 1]; ++ch) {
                const std::uint32_t i = level.children[ch];
                add(d, above.diagonal[i]);
                for (std::uint32_t e = above.rowStart[i]; e < above.rowStart[i + 1]; ++e) {
                    const std::uint32_t t = level.target[e];
                    add(t == kToDiagonal ? d : level.offDiagonal[t], above.offDiagonal[e]);
                }
            }
            level.diagonal[a] = d;
        }
        publishBlocks(level);
    }
    // The coarsest level, factorised when it is small; an empty row (every node in it pinned) stands as
    // the identity, its right-hand side zero.
    Level& last = coarse_.back();
    dense_ = last.rows <= kDenseRows;
    if (!dense_) return;
    const auto n = static_cast<Eigen::Index>(3 * last.rows);
    DenseMatrix m = DenseMatrix::Zero(n, n);
    auto put = [&](std::size_t row, std::size_t column, const SymmetricBlock& b) {
        const Eigen::Index r0 = 3 * static_cast<Eigen::Index>(row), c0 = 3 * static_cast<Eigen::Index>(column);
        const double entries[3][3] = {{b[0], b[1], b[2]}, {b[1], b[3], b[4]}, {b[2], b[4], b[5]}};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) m(r0 + i, c0 + j) = entries[i][j];
    };
    for (std::size_t a = 0; a < last.rows; ++a) {
        put(a, a, last.diagonal[a][0] > 0 ? last.diagonal[a] : SymmetricBlock{1, 0, 0, 1, 0, 1});
        for (std::uint32_t e = last.rowStart[a]; e < last.rowStart[a + 1]; ++e)
            put(a, last.column[e], last.offDiagonal[e]);
    }
    factor_.compute(m);
    dense_ = factor_.info() == Eigen::Success;
}

void MultilevelPreconditioner::residual(const Level& level, const kernels::Field& e, kernels::Field& out) {
    kernels::blockProduct(level.matrix(), e, &level.r, out, {0, level.paddedRows()});
}

void MultilevelPreconditioner::smooth(Level& level, bool fromZero) {
    const kernels::RowRange all{0, level.paddedRows()};
    if (!fromZero) kernels::blockProduct(level.matrix(), level.e, nullptr, level.t, all);  // t = A e
    // e = ω D⁻¹ r from zero, else e += ω D⁻¹ (r - A e).
    (void)kernels::smoothPass(all, kSmoothingWeight, level.r, fromZero ? nullptr : &level.t, level.inverseBlocks,
                              level.e);
}

void MultilevelPreconditioner::solveCoarsest(Level& level) {
    if (dense_) {
        DenseVector b(static_cast<Eigen::Index>(3 * level.rows));
        for (std::size_t a = 0; a < level.rows; ++a)
            b.segment<3>(3 * static_cast<Eigen::Index>(a)) =
                level.diagonal[a][0] > 0 ? Vec3(level.r.x[a], level.r.y[a], level.r.z[a]) : Vec3::Zero();
        factor_.solveInPlace(b);
        for (std::size_t a = 0; a < level.rows; ++a) {
            const auto i = 3 * static_cast<Eigen::Index>(a);
            level.e.x[a] = b(i), level.e.y[a] = b(i + 1), level.e.z[a] = b(i + 2);
        }
        return;
    }
    smooth(level, true);
    for (int sweep = 1; sweep < kCoarsestSweeps; ++sweep) smooth(level, false);
}

void MultilevelPreconditioner::twoCycles(std::size_t index) {
    Level& level = coarse_[index];
    if (index + 1 == coarse_.size() && dense_) {  // solved exactly: a second solve would find nothing left
        solveCoarsest(level);
        return;
    }
    cycle(index);
    std::swap(level.held, level.e);
    residual(level, level.held, level.t);
    std::swap(level.r, level.t);
    cycle(index);
    for (std::size_t a = 0; a < level.rows; ++a)
        level.e.x[a] += level.held.x[a], level.e.y[a] += level.held.y[a], level.e.z[a] += level.held.z[a];
}

void MultilevelPreconditioner::cycle(std::size_t index) {
    Level& level = coarse_[index];
    if (index + 1 == coarse_.size()) {
        solveCoarsest(level);
        return;
    }
    Level& next = coarse_[index + 1];
    smooth(level, true);
    residual(level, level.e, level.t);
    for (std::size_t b = 0; b < next.rows; ++b) {
        double sx = 0, sy = 0, sz = 0;
        for (std::uint32_t ch = next.childStart[b]; ch < next.childStart[b + 1]; ++ch) {
            const std::uint32_t i = next.children[ch];
            sx += level.t.x[i], sy += level.t.y[i], sz += level.t.z[i];
        }
        next.r.x[b] = sx, next.r.y[b] = sy, next.r.z[b] = sz;
    }
    twoCycles(index + 1);
    for (std::size_t a = 0; a < level.rows; ++a) {
        const std::uint32_t b = next.aggregateOf[a];
        level.e.x[a] += next.e.x[b], level.e.y[a] += next.e.y[b], level.e.z[a] += next.e.z[b];
    }
    smooth(level, false);
}

kernels::Sums MultilevelPreconditioner::apply(const kernels::SystemRows& fine, const kernels::SymmetricBlocks& inverse,
                                              const kernels::Field& r, kernels::Field& z, OwnedWorkerPool& pool,
                                              bool smoothed) {
    const std::size_t rows = fine.rows;
    partial_.resize(kernels::chunksOf(rows));
    auto forEachChunk = [&](auto&& task) {
        pool.forEach(kernels::chunksOf(rows), [&](std::size_t chunk) { task(chunk, kernels::chunkRows(chunk, rows)); });
    };
    auto total = [&] {
        kernels::Sums sums;
        for (const kernels::Sums& part : partial_)
            sums.r2 += part.r2, sums.rz += part.rz, sums.rowMax2 = std::max(sums.rowMax2, part.rowMax2);
        return sums;
    };
    if (coarse_.empty()) {  // no coarse level: block-Jacobi
        forEachChunk([&](std::size_t chunk, kernels::RowRange range) {
            partial_[chunk] = kernels::smoothPass(range, 1.0, r, nullptr, inverse, z);
        });
        return total();
    }
    product_.resize(rows);
    auto multiply = [&](const kernels::Field& y) {
        forEachChunk([&](std::size_t, kernels::RowRange range) { kernels::multiply(fine, y, product_, range); });
    };
    if (!smoothed)
        forEachChunk([&](std::size_t, kernels::RowRange range) {
            kernels::smoothPass(range, kSmoothingWeight, r, nullptr, inverse, z);
        });
    multiply(z);
    Level& first = coarse_.front();
    for (std::size_t a = 0; a < first.rows; ++a) {
        double sx = 0, sy = 0, sz = 0;
        for (std::uint32_t ch = first.childStart[a]; ch < first.childStart[a + 1]; ++ch) {
            const std::uint32_t i = first.children[ch];
            sx += r.x[i] - product_.x[i], sy += r.y[i] - product_.y[i], sz += r.z[i] - product_.z[i];
        }
        first.r.x[a] = sx, first.r.y[a] = sy, first.r.z[a] = sz;
    }
    twoCycles(0);  // level 1 gets two cycles as every coarser level does (a W-cycle throughout)
    forEachChunk([&](std::size_t, kernels::RowRange range) {
        for (std::size_t k = range.first; k < std::min(range.end, count_); ++k) {
            if (excluded_[k]) continue;
            const std::uint32_t a = first.aggregateOf[k];
            z.x[k] += first.e.x[a], z.y[k] += first.e.y[a], z.z[k] += first.e.z[a];
        }
    });
    multiply(z);
    forEachChunk([&](std::size_t chunk, kernels::RowRange range) {
        partial_[chunk] = kernels::smoothPass(range, kSmoothingWeight, r, &product_, inverse, z);
    });
    return total();
}

}  // namespace hapticut::physics
