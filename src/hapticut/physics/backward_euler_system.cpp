// Assembly of the backward-Euler system, and its rows laid out for the kernels (solver_kernels.h).
#include "hapticut/physics/backward_euler_system.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "hapticut/common/assert.h"
#include "hapticut/common/reserve.h"
#include "hapticut/physics/spring_forces.h"

namespace hapticut::physics {

namespace {

/// Writes couplings' slots, c0 I + u uᵀ in single precision, through addresses held for a whole pass:
/// written through the members, every store made the compiler load them again, and the assembly's
/// scatter cost more than its kernel.
struct CouplingSlots {
    float* __restrict c0;
    float* __restrict ux;
    float* __restrict uy;
    float* __restrict uz;
    explicit CouplingSlots(kernels::SlicedCouplings& s)
        : c0(s.c0.data()), ux(s.ux.data()), uy(s.uy.data()), uz(s.uz.data()) {}
    void set(std::uint32_t slot, float c, float x, float y, float z) const {
        c0[slot] = c, ux[slot] = x, uy[slot] = y, uz[slot] = z;
    }
};

}  // namespace

void BackwardEulerSystem::reserve(std::size_t nodes, std::size_t springs) {
    const std::size_t rows = nodes + kernels::kSliceRows;
    reserveTouched(unknownOf_, nodes);
    reserveTouched(diagonal_, rows);
    reserveTouched(rowStart_, nodes + 1);
    for (auto* list : {&endA_, &endB_, &slotA_, &slotB_, &ordered_, &position_}) reserveTouched(*list, springs);
    reserveTouched(bucketStart_, 2 * (rows / kernels::kChunkRows + 1) + 1);
    reserveTouched(column_, nodes);
    reserveTouched(restingSum_, nodes);
    reserveTouched(restingOf_, rows);
    for (auto* field : {&rhs_.x, &rhs_.y, &rhs_.z}) reserveTouched(*field, rows);
    for (auto* blocks : {&toResting_, &inverseBlock_})
        for (auto* a : {&blocks->xx, &blocks->xy, &blocks->xz, &blocks->yy, &blocks->yz, &blocks->zz})
            reserveTouched(*a, rows);
    // Slices are as wide as their widest row: room for half as many slots again as there are couplings.
    const std::size_t slots = 3 * springs + 4 * rows;
    reserveTouched(sliced_.sliceBegin, rows / kernels::kSliceRows + 2);
    reserveTouched(sliced_.other, slots);
    for (auto* a : {&sliced_.c0, &sliced_.ux, &sliced_.uy, &sliced_.uz}) reserveTouched(*a, slots);
}

void BackwardEulerSystem::resize(std::size_t nodes) { unknownOf_.resize(std::max(nodes, unknownOf_.size()), kResting); }

void BackwardEulerSystem::setBlock(kernels::SymmetricBlocks& blocks, std::size_t k, const Mat3& m) {
    const auto f = [](double value) { return static_cast<float>(value); };
    blocks.xx[k] = f(m(0, 0)), blocks.xy[k] = f(m(0, 1)), blocks.xz[k] = f(m(0, 2));
    blocks.yy[k] = f(m(1, 1)), blocks.yz[k] = f(m(1, 2)), blocks.zz[k] = f(m(2, 2));
}

void BackwardEulerSystem::assemble(const MassSpringModel& model, double h, SolveRegion region,
                                   std::span<const Vec3> startVelocity, OwnedWorkerPool* pool) {
    // The first linearisation adds h² K v to the right-hand side; a correction subtracts M (v - v0).
    const bool correction = !startVelocity.empty();
    const Nodes& n = model.nodes;
    const Springs& s = model.springs;
    const std::vector<Vec3>& x = n.position;
    const std::vector<Vec3>& v = n.velocity;
    const double h2 = h * h;
    OwnedWorkerPool calling;  // no threads: every chunk on the calling thread
    OwnedWorkerPool& threads = pool ? *pool : calling;
    // Capacity is reserved for every node and spring: these resizes never allocate in a step.
    const std::size_t count = region.nodes.size();
    count_ = count;
    rows_ = (count + kernels::kSliceRows - 1) / kernels::kSliceRows * kernels::kSliceRows;
    diagonal_.resize(rows_);
    toResting_.resize(rows_);
    inverseBlock_.resize(rows_);
    rhs_.resize(rows_);
    if (scratch_.size() != threads.threads()) scratch_.resize(threads.threads());  // once per thread count
    for (std::uint32_t i : region.touched) unknownOf_[i] = kResting;
    const Vec3 g = model.gravity_m_per_s2;
    threads.forEach(rowChunks(), [&](std::size_t chunk) {
        const kernels::RowRange range = kernels::chunkRows(chunk, rows_);
        for (std::size_t k = range.first; k < std::min(range.end, count); ++k) {
            const std::uint32_t i = region.nodes[k];
            unknownOf_[i] = static_cast<std::uint32_t>(k);
            const double ka = n.anchorStiffness[i], da = n.anchorDamping[i];
            const Vec3 f = n.externalForce[i] - ka * (x[i] - n.restPosition[i]) - da * v[i] +
                           (n.inverseMass[i] > 0 ? Vec3(n.mass[i] * g) : Vec3::Zero());
            const Vec3 b = h * f - (correction ? Vec3(n.mass[i] * (v[i] - startVelocity[k])) : Vec3(h2 * ka * v[i]));
            rhs_.x[k] = b.x(), rhs_.y[k] = b.y(), rhs_.z[k] = b.z();
            diagonal_[k] = n.mass[i] + h * da + h2 * ka;
        }
        for (std::size_t k = std::max(range.first, count); k < range.end; ++k) {  // the padding rows are zero
            diagonal_[k] = 0;
            rhs_.x[k] = rhs_.y[k] = rhs_.z[k] = 0;
        }
    });
    for (const PointSpring& tool : model.tools) {
        if (!tool.active) continue;
        const Vec3 held = tool.heldPoint(x), force = tool.forceAt(held);
        // A clamped force enters the matrix by its secant, the stiffness that gives the clamped force at
        // the held point and none at the device, so a step never carries the tissue past the device.
        // Left out (a constant force), it did: a scalpel's 3.3 N on tissue a cut had just freed, a quarter
        // of it on a node of half a milligram, threw that node 24 mm beyond the blade in one 4 ms step.
        const double unclamped = (tool.stiffness_N_per_m * (held - tool.anchor_m) - tool.bias_N).norm();
        const double secant = unclamped > tool.maxForce_N ? tool.maxForce_N / unclamped : 1.0;
        const double kt = force != Vec3::Zero() ? tool.scale * secant * tool.stiffness_N_per_m : 0.0;
        // The spring's stiffness k w w^T lumped by rows to k w_i: with weights that sum to 1 the lumped
        // matrix exceeds the true one by the weights' variance, so the solve stays definite and stable.
        for (std::uint32_t c = 0; c < tool.count; ++c) {
            const std::uint32_t k = unknownOf_[tool.nodes[c]];
            if (k == kResting) continue;  // the active region keeps a tool's nodes awake; a full solve has all
            const double w = tool.weights[c];
            const Vec3 b = h * w * force + (correction ? Vec3::Zero() : Vec3(h2 * kt * w * v[tool.nodes[c]]));
            rhs_.x[k] -= b.x(), rhs_.y[k] -= b.y(), rhs_.z[k] -= b.z();
            diagonal_[k] += h2 * kt * w;
        }
    }
    if (region.layout == 0 || region.layout != layout_) layOut(s, region);
    HAPTICUT_ASSERT(layoutMatches(s, region));
    layout_ = region.layout;
    for (Mat3& resting : restingSum_) resting.setZero();
    // The springs' terms, bucket by bucket (layOut): the chunks' own on the pool's threads; then those
    // between neighbouring chunks, every other boundary at a time, so that no two threads write a row;
    // then the few that reach further, here.
    const std::size_t chunks = rowChunks();
    auto springsOf = [&](std::size_t bucket, unsigned worker) {
        assembleSprings(model, h, !correction, bucketStart_[bucket], bucketStart_[bucket + 1], scratch_[worker]);
    };
    threads.forEach(chunks, springsOf);
    for (std::size_t parity = 0; parity < 2; ++parity)
        threads.forEach((chunks - parity) / 2,
                        [&](std::size_t i, unsigned worker) { springsOf(chunks + 2 * i + parity, worker); });
    springsOf(2 * chunks - 1, 0);
    constexpr std::size_t kSlice = kernels::kSliceRows;
    threads.forEach(rowChunks(), [&](std::size_t chunk) {
        const kernels::RowRange range = kernels::chunkRows(chunk, rows_);
        for (std::size_t k = range.first; k < std::min(range.end, count); ++k) {
            if (n.inverseMass[region.nodes[k]] == 0) {
                // A pinned node's row is left out: no terms, no right-hand side, no preconditioner, so its
                // unknown stays zero. (Its slots are zeroed here rather than left out of the layout: a node
                // is pinned or freed without the layout changing.)
                diagonal_[k] = 0;
                setBlock(toResting_, k, Mat3::Zero());
                rhs_.x[k] = rhs_.y[k] = rhs_.z[k] = 0;
                const std::size_t first = sliced_.sliceBegin[k / kSlice] + k % kSlice;
                const CouplingSlots slots(sliced_);
                for (std::uint32_t j = 0; j < rowStart_[k + 1] - rowStart_[k]; ++j)
                    slots.set(static_cast<std::uint32_t>(first + j * kSlice), 0, 0, 0, 0);
                continue;
            }
            setBlock(toResting_, k, restingOf_[k] == kNoResting ? Mat3::Zero() : restingSum_[restingOf_[k]]);
        }
        for (std::size_t k = std::max(range.first, count); k < range.end; ++k) setBlock(toResting_, k, Mat3::Zero());
        // The preconditioner: each row's diagonal block, m + h d + h² k and its springs' blocks, as the
        // product reads them (in single precision: a preconditioner need not be exact), inverted by the
        // SIMD kernel a slice at a time.
        kernels::invertRowBlocks(matrix(), inverseBlock_, range);
    });
}

void BackwardEulerSystem::assembleSprings(const MassSpringModel& model, double h, bool firstLinearisation,
                                          std::size_t first, std::size_t end, kernels::SpringJacobians& chunk) {
    // The springs' terms come from the SIMD kernel a chunk at a time. Each spring writes its coupling to
    // its slot in both rows and its right-hand side to both ends; the rows' diagonal blocks are summed
    // from their couplings afterwards, row by row, so that no 3×3 block is scattered.
    const std::vector<Vec3>& x = model.nodes.position;
    const kernels::SpringArrays arrays = springArrays(model.springs);
    // The arrays this loop scatters into, held in registers: written through the members, every store
    // made the compiler load their addresses again, and the loop cost more than the kernel.
    double* __restrict rx = rhs_.x.data();
    double* __restrict ry = rhs_.y.data();
    double* __restrict rz = rhs_.z.data();
    const CouplingSlots slots(sliced_);
    const std::uint32_t* __restrict endA = endA_.data();
    const std::uint32_t* __restrict endB = endB_.data();
    const std::uint32_t* __restrict slotA = slotA_.data();
    const std::uint32_t* __restrict slotB = slotB_.data();
    for (std::size_t begin = first; begin < end; begin += kernels::SpringJacobians::kSprings) {
        const std::size_t size = std::min(kernels::SpringJacobians::kSprings, end - begin);
        kernels::springJacobians(arrays, ordered_.data() + begin, size, coordinates(x.data()),
                                 coordinates(model.nodes.velocity.data()), h, firstLinearisation, chunk);
        for (std::size_t i = 0; i < size; ++i) {
            const std::size_t e = begin + i;
            const std::uint32_t ka = endA[e], kb = endB[e];
            const bool inner = ka != kResting && kb != kResting;
            if (!chunk.apart[i]) {  // coincident ends have no direction, as in the explicit force
                if (inner) slots.set(slotA[e], 0, 0, 0, 0), slots.set(slotB[e], 0, 0, 0, 0);
                continue;
            }
            const double bx = chunk.bx[i], by = chunk.by[i], bz = chunk.bz[i];
            if (inner) {
                rx[ka] += bx, ry[ka] += by, rz[ka] += bz;
                rx[kb] -= bx, ry[kb] -= by, rz[kb] -= bz;
                const auto c0 = static_cast<float>(chunk.c0[i]), ux = static_cast<float>(chunk.ux[i]);
                const auto uy = static_cast<float>(chunk.uy[i]), uz = static_cast<float>(chunk.uz[i]);
                slots.set(slotA[e], c0, ux, uy, uz), slots.set(slotB[e], c0, ux, uy, uz);
                continue;
            }
            if (ka != kResting) rx[ka] += bx, ry[ka] += by, rz[ka] += bz;
            if (kb != kResting) rx[kb] -= bx, ry[kb] -= by, rz[kb] -= bz;
            if (ka != kb) {  // one end awake
                const Vec3 u(chunk.ux[i], chunk.uy[i], chunk.uz[i]);
                Mat3& resting = restingSum_[restingOf_[ka != kResting ? ka : kb]];
                resting += u * u.transpose();
                resting.diagonal().array() += chunk.c0[i];
            }
        }
    }
}

bool BackwardEulerSystem::layoutMatches(const Springs& s, SolveRegion region) const {
    if (endA_.size() != region.springs.size() || bucketStart_.size() != 2 * rowChunks() + 1) return false;
    for (std::size_t e = 0; e < region.springs.size(); ++e) {
        const std::uint32_t p = position_[e];
        if (p >= ordered_.size() || ordered_[p] != region.springs[e] || endA_[p] != unknownOf_[s.a[ordered_[p]]] ||
            endB_[p] != unknownOf_[s.b[ordered_[p]]])
            return false;
    }
    return rowStart_.size() == count_ + 1;
}

void BackwardEulerSystem::layOut(const Springs& s, SolveRegion region) {
    ++layoutsMade_;
    constexpr std::size_t kSlice = kernels::kSliceRows;
    const std::size_t count = count_, listed = region.springs.size();
    // Capacity is reserved for every node and spring: these resizes never allocate in a step.
    for (auto* list : {&endA_, &endB_, &slotA_, &slotB_, &ordered_, &position_}) list->resize(listed);
    // Each spring's bucket, for C chunks of rows: c < C when its awake ends lie in chunk c; C + c when they
    // lie in chunks c and c + 1; 2C - 1 when further apart. A counting sort puts the springs in bucket
    // order, each bucket in the list's order.
    const std::size_t chunks = rowChunks(), buckets = 2 * chunks;
    bucketStart_.assign(buckets + 1, 0);
    auto bucketOf = [&](std::uint32_t ka, std::uint32_t kb) -> std::size_t {
        if (ka == kResting) std::swap(ka, kb);
        if (ka == kResting) return buckets - 1;
        const std::size_t chunkA = ka / kernels::kChunkRows;
        const std::size_t chunkB = kb == kResting ? chunkA : kb / kernels::kChunkRows;
        if (chunkA == chunkB) return chunkA;
        const std::size_t low = std::min(chunkA, chunkB);
        return std::max(chunkA, chunkB) == low + 1 ? chunks + low : buckets - 1;
    };
    for (std::uint32_t spring : region.springs)
        ++bucketStart_[bucketOf(unknownOf_[s.a[spring]], unknownOf_[s.b[spring]]) + 1];
    for (std::size_t b = 0; b < buckets; ++b) bucketStart_[b + 1] += bucketStart_[b];
    column_.assign(buckets, 0);  // while sorting: each bucket's next place
    for (std::size_t e = 0; e < listed; ++e) {
        const std::uint32_t spring = region.springs[e];
        const std::uint32_t ka = unknownOf_[s.a[spring]], kb = unknownOf_[s.b[spring]];
        const std::size_t b = bucketOf(ka, kb);
        const std::uint32_t p = bucketStart_[b] + column_[b]++;
        position_[e] = p, ordered_[p] = spring, endA_[p] = ka, endB_[p] = kb;
    }
    // The rows' lengths, a row's couplings in bucket order; each row with springs to resting neighbours
    // gets its block.
    rowStart_.assign(count + 1, 0);
    restingOf_.assign(count, kNoResting);
    std::size_t resting = 0;
    for (std::size_t p = 0; p < listed; ++p) {
        const std::uint32_t ka = endA_[p], kb = endB_[p];
        if (ka != kResting && kb != kResting) {
            ++rowStart_[ka + 1], ++rowStart_[kb + 1];
        } else if (ka != kb) {
            std::uint32_t& at = restingOf_[ka != kResting ? ka : kb];
            if (at == kNoResting) at = static_cast<std::uint32_t>(resting++);
        }
    }
    restingSum_.resize(resting);
    for (std::size_t k = 0; k < count; ++k) rowStart_[k + 1] += rowStart_[k];
    // Each slice as wide as its widest row; every slot starts as a zero coupling of its row to itself.
    const std::size_t slices = rows_ / kSlice;
    sliced_.sliceBegin.resize(slices + 1);
    std::size_t slots = 0;
    for (std::size_t slice = 0; slice < slices; ++slice) {
        sliced_.sliceBegin[slice] = static_cast<std::uint32_t>(slots);
        std::uint32_t width = 0;
        for (std::size_t k = slice * kSlice; k < std::min(count, (slice + 1) * kSlice); ++k)
            width = std::max(width, rowStart_[k + 1] - rowStart_[k]);
        slots += width * kSlice;
    }
    sliced_.sliceBegin[slices] = static_cast<std::uint32_t>(slots);
    sliced_.other.resize(slots);
    for (auto* a : {&sliced_.c0, &sliced_.ux, &sliced_.uy, &sliced_.uz}) a->assign(slots, 0.0f);
    for (std::size_t slice = 0; slice < slices; ++slice)
        for (std::size_t slot = sliced_.sliceBegin[slice]; slot < sliced_.sliceBegin[slice + 1]; ++slot)
            sliced_.other[slot] = static_cast<std::int32_t>(slice * kSlice + slot % kSlice);
    // Each spring between two unknowns takes the next column of both its ends' rows.
    column_.assign(count, 0);
    auto nextSlot = [&](std::uint32_t k, std::uint32_t other) {
        const auto slot =
            static_cast<std::uint32_t>(sliced_.sliceBegin[k / kSlice] + column_[k]++ * kSlice + k % kSlice);
        sliced_.other[slot] = static_cast<std::int32_t>(other);
        return slot;
    };
    for (std::size_t p = 0; p < listed; ++p) {
        if (endA_[p] == kResting || endB_[p] == kResting) continue;
        slotA_[p] = nextSlot(endA_[p], endB_[p]);
        slotB_[p] = nextSlot(endB_[p], endA_[p]);
    }
}

bool BackwardEulerSystem::movesApartMoreThan(const Springs& springs, SolveRegion region, std::span<const Vec3> motion,
                                             double fraction, OwnedWorkerPool* pool) const {
    constexpr std::size_t kChunk = 4 * kernels::kChunkRows;  // springs
    const std::size_t listed = region.springs.size(), chunks = (listed + kChunk - 1) / kChunk;
    const double fraction2 = fraction * fraction;
    std::atomic<bool> found{false};  // once set, the chunks not yet begun are skipped
    // The springs as the last assembly laid them out (the same region): their unknowns are at hand, where
    // looking up each end's cost two dependent loads a spring (the check was 10.5% of a 9,714 heart's
    // step, 8.6% since).
    HAPTICUT_ASSERT(layoutMatches(springs, region));
    auto search = [&](std::size_t chunk) {
        if (found.load(std::memory_order_relaxed)) return;
        // The arrays and the end held in this call's own variables: captured, each was loaded again for
        // every spring.
        const double* __restrict restLength = springs.restLength.data();
        const std::uint32_t* __restrict ordered = ordered_.data();
        const std::uint32_t* __restrict endA = endA_.data();
        const std::uint32_t* __restrict endB = endB_.data();
        const Vec3* __restrict moved = motion.data();
        const std::size_t end = std::min(listed, (chunk + 1) * kChunk);
        for (std::size_t p = chunk * kChunk; p < end; ++p) {
            const double rest = restLength[ordered[p]];
            if (rest < 1e-9) continue;
            const std::uint32_t ka = endA[p], kb = endB[p];
            const Vec3 ma = ka != kResting ? moved[ka] : Vec3::Zero(), mb = kb != kResting ? moved[kb] : Vec3::Zero();
            if ((mb - ma).squaredNorm() > fraction2 * rest * rest) {
                found.store(true, std::memory_order_relaxed);
                return;
            }
        }
    };
    OwnedWorkerPool calling;
    (pool ? *pool : calling).forEach(chunks, search);
    return found.load(std::memory_order_relaxed);
}

}  // namespace hapticut::physics
