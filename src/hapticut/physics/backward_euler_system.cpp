// Assembly of the backward-Euler system, and its rows laid out for the kernels (solver_kernels.h).
#include "hapticut/physics/backward_euler_system.h"

#include <algorithm>
#include <cmath>

#include "hapticut/common/assert.h"
#include "hapticut/common/reserve.h"
#include "hapticut/physics/spring_forces.h"

namespace hapticut::physics {

void BackwardEulerSystem::reserve(std::size_t nodes, std::size_t springs) {
    const std::size_t rows = nodes + kernels::kSliceRows;
    reserveTouched(unknownOf_, nodes);
    reserveTouched(diagonal_, rows);
    reserveTouched(rowStart_, nodes + 1);
    for (auto* list : {&endA_, &endB_, &slotA_, &slotB_}) reserveTouched(*list, springs);
    reserveTouched(column_, nodes);
    reserveTouched(restingSum_, nodes);
    reserveTouched(restingOf_, rows);
    reserveTouched(pinned_, rows);
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
                                   std::span<const Vec3> startVelocity) {
    // The first linearisation adds h² K v to the right-hand side; a correction subtracts M (v - v0).
    const bool correction = !startVelocity.empty();
    const Nodes& n = model.nodes;
    const Springs& s = model.springs;
    const std::vector<Vec3>& x = n.position;
    const std::vector<Vec3>& v = n.velocity;
    const double h2 = h * h;
    // Capacity is reserved for every node and spring: these resizes never allocate in a step.
    const std::size_t count = region.nodes.size();
    count_ = count;
    rows_ = (count + kernels::kSliceRows - 1) / kernels::kSliceRows * kernels::kSliceRows;
    diagonal_.assign(rows_, 0.0);
    toResting_.resize(rows_);
    inverseBlock_.resize(rows_);
    pinned_.assign(rows_, 0);
    restingSum_.clear();
    restingOf_.assign(count, kNoResting);
    rhs_.resize(rows_);
    for (std::uint32_t i : region.touched) unknownOf_[i] = kResting;
    const Vec3 g = model.gravity_m_per_s2;
    for (std::uint32_t k = 0; k < count; ++k) {
        const std::uint32_t i = region.nodes[k];
        unknownOf_[i] = k;
        const double ka = n.anchorStiffness[i], da = n.anchorDamping[i];
        const Vec3 f = n.externalForce[i] - ka * (x[i] - n.restPosition[i]) - da * v[i] +
                       (n.inverseMass[i] > 0 ? Vec3(n.mass[i] * g) : Vec3::Zero());
        const Vec3 b = h * f - (correction ? Vec3(n.mass[i] * (v[i] - startVelocity[k])) : Vec3(h2 * ka * v[i]));
        rhs_.x[k] = b.x(), rhs_.y[k] = b.y(), rhs_.z[k] = b.z();
        diagonal_[k] = n.mass[i] + h * da + h2 * ka;
    }
    for (const PointSpring& tool : model.tools) {
        if (!tool.active) continue;
        const Vec3 force = tool.forceOnTool(x);
        // A clamped force no longer grows with the press: its stiffness is left out of the matrix.
        const Vec3 p = tool.heldPoint(x);
        const bool linear = force != Vec3::Zero() &&
                            (tool.stiffness_N_per_m * (p - tool.anchor_m) - tool.bias_N).norm() <= tool.maxForce_N;
        const double kt = linear ? tool.scale * tool.stiffness_N_per_m : 0.0;
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
    // The springs' terms come from the SIMD kernel a chunk at a time. Each spring writes its coupling to
    // its slot in both rows and its right-hand side to both ends; the rows' diagonal blocks are summed
    // from their couplings afterwards, row by row, so that no 3×3 block is scattered.
    const kernels::SpringArrays arrays = springArrays(s);
    kernels::SpringJacobians& chunk = chunk_;  // one chunk's terms (14 KB: a member, not on the stack)
    for (std::size_t begin = 0; begin < region.springs.size(); begin += kernels::SpringJacobians::kSprings) {
        const std::size_t size = std::min(kernels::SpringJacobians::kSprings, region.springs.size() - begin);
        kernels::springJacobians(arrays, region.springs.data() + begin, size, x.size(), coordinates(x.data()),
                                 coordinates(v.data()), h, !correction, chunk);
        for (std::size_t i = 0; i < size; ++i) {
            const std::size_t e = begin + i;
            const std::uint32_t ka = endA_[e], kb = endB_[e];
            const bool inner = ka != kResting && kb != kResting;
            if (!chunk.apart[i]) {  // coincident ends have no direction, as in the explicit force
                if (inner) setCoupling(slotA_[e], 0, 0, 0, 0), setCoupling(slotB_[e], 0, 0, 0, 0);
                continue;
            }
            const double bx = chunk.bx[i], by = chunk.by[i], bz = chunk.bz[i];
            if (ka != kResting) rhs_.x[ka] += bx, rhs_.y[ka] += by, rhs_.z[ka] += bz;
            if (kb != kResting) rhs_.x[kb] -= bx, rhs_.y[kb] -= by, rhs_.z[kb] -= bz;
            const double c0 = chunk.c0[i], ux = chunk.ux[i], uy = chunk.uy[i], uz = chunk.uz[i];
            if (inner) {
                setCoupling(slotA_[e], c0, ux, uy, uz), setCoupling(slotB_[e], c0, ux, uy, uz);
            } else {
                std::uint32_t& at = restingOf_[ka != kResting ? ka : kb];
                if (at == kNoResting)
                    at = static_cast<std::uint32_t>(restingSum_.size()), restingSum_.push_back(Mat3::Zero());
                const Vec3 u(ux, uy, uz);
                Mat3& resting = restingSum_[at];
                resting += u * u.transpose();
                resting.diagonal().array() += c0;
            }
        }
    }
    constexpr std::size_t kSlice = kernels::kSliceRows;
    for (std::uint32_t k = 0; k < count; ++k) {
        if (n.inverseMass[region.nodes[k]] == 0) {
            // A pinned node's row is left out: no terms, no right-hand side, no preconditioner, so its
            // unknown stays zero. (Its slots are zeroed here rather than left out of the layout: a node
            // is pinned or freed without the layout changing.)
            pinned_[k] = 1;
            diagonal_[k] = 0;
            setBlock(toResting_, k, Mat3::Zero());
            rhs_.x[k] = rhs_.y[k] = rhs_.z[k] = 0;
            const std::size_t first = sliced_.sliceBegin[k / kSlice] + k % kSlice;
            for (std::uint32_t j = 0; j < rowStart_[k + 1] - rowStart_[k]; ++j)
                setCoupling(static_cast<std::uint32_t>(first + j * kSlice), 0, 0, 0, 0);
            continue;
        }
        setBlock(toResting_, k, restingOf_[k] == kNoResting ? Mat3::Zero() : restingSum_[restingOf_[k]]);
    }
    for (std::size_t k = count; k < rows_; ++k) {  // the padding rows are zero throughout
        setBlock(toResting_, k, Mat3::Zero());
        rhs_.x[k] = rhs_.y[k] = rhs_.z[k] = 0;
    }
    // The preconditioner: each row's diagonal block, m + h d + h² k and its springs' blocks, as the
    // product reads them (in single precision: a preconditioner need not be exact), inverted by the
    // SIMD kernel a slice at a time.
    kernels::invertRowBlocks(matrix(), inverseBlock_);
}

void BackwardEulerSystem::setCoupling(std::uint32_t slot, double c0, double ux, double uy, double uz) {
    sliced_.c0[slot] = static_cast<float>(c0), sliced_.ux[slot] = static_cast<float>(ux);
    sliced_.uy[slot] = static_cast<float>(uy), sliced_.uz[slot] = static_cast<float>(uz);
}

bool BackwardEulerSystem::layoutMatches(const Springs& s, SolveRegion region) const {
    if (endA_.size() != region.springs.size()) return false;
    for (std::size_t e = 0; e < region.springs.size(); ++e)
        if (endA_[e] != unknownOf_[s.a[region.springs[e]]] || endB_[e] != unknownOf_[s.b[region.springs[e]]])
            return false;
    return rowStart_.size() == count_ + 1;
}

void BackwardEulerSystem::layOut(const Springs& s, SolveRegion region) {
    constexpr std::size_t kSlice = kernels::kSliceRows;
    const std::size_t count = count_, listed = region.springs.size();
    // Capacity is reserved for every node and spring: these resizes never allocate in a step.
    endA_.resize(listed), endB_.resize(listed), slotA_.resize(listed), slotB_.resize(listed);
    // The rows' lengths, a row's couplings in the order of the springs' list.
    rowStart_.assign(count + 1, 0);
    for (std::size_t e = 0; e < listed; ++e) {
        const std::uint32_t ka = unknownOf_[s.a[region.springs[e]]], kb = unknownOf_[s.b[region.springs[e]]];
        endA_[e] = ka, endB_[e] = kb;
        if (ka != kResting && kb != kResting) ++rowStart_[ka + 1], ++rowStart_[kb + 1];
    }
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
    for (std::size_t e = 0; e < listed; ++e) {
        if (endA_[e] == kResting || endB_[e] == kResting) continue;
        slotA_[e] = nextSlot(endA_[e], endB_[e]);
        slotB_[e] = nextSlot(endB_[e], endA_[e]);
    }
}

double BackwardEulerSystem::largestRelativeMotion(const Springs& springs, SolveRegion region,
                                                  std::span<const Vec3> motion) const {
    double largest2 = 0;
    for (std::uint32_t e : region.springs) {
        const double rest = springs.restLength[e];
        if (rest < 1e-9) continue;
        const std::uint32_t ka = unknownOf_[springs.a[e]], kb = unknownOf_[springs.b[e]];
        const Vec3 ma = ka != kResting ? motion[ka] : Vec3::Zero(), mb = kb != kResting ? motion[kb] : Vec3::Zero();
        largest2 = std::max(largest2, (mb - ma).squaredNorm() / (rest * rest));
    }
    return std::sqrt(largest2);
}

}  // namespace hapticut::physics
