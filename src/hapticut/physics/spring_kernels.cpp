// The springs' forces, and their Jacobians for the implicit step, as SIMD kernels: this file is compiled
// once per target by Highway's foreach_target, and the HWY_ONCE part at the end dispatches to the best
// one the machine supports (solver_kernels.cpp's forceTarget chooses for both files).
//
// A spring's force takes a square root, a division and some thirty products, which the vector lanes
// share; its two scattered additions to the node forces stay scalar, in the springs' order, so that no
// two lanes ever add to the same node at once. The arithmetic is the scalar formula's, operation for
// operation and without fused multiply-adds (CMakeLists.txt compiles this file with -ffp-contract=off),
// so every target gives the scalar loop's forces to the bit and a golden force trace does not depend on
// the machine.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "hapticut/physics/spring_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>

#include "hapticut/physics/spring_kernels.h"

#ifndef HAPTICUT_SPRING_KERNELS_SCALAR
#define HAPTICUT_SPRING_KERNELS_SCALAR
namespace hapticut::physics::kernels {

/// Closer than this (squared, m²) a spring's ends have no direction; a fresh cut can produce them.
inline constexpr double kCoincident2 = 1e-24;

/// Spring k's force on its end a, scalar (its end b gets the opposite); false for coincident ends.
inline bool springForce(const SpringArrays& s, std::uint32_t k, const double* __restrict x, const double* __restrict v,
                        double& fx, double& fy, double& fz) {
    const std::size_t ia = 3 * std::size_t{s.a[k]}, ib = 3 * std::size_t{s.b[k]};
    const double dx = x[ib] - x[ia], dy = x[ib + 1] - x[ia + 1], dz = x[ib + 2] - x[ia + 2];
    const double len2 = dx * dx + dy * dy + dz * dz;
    if (len2 < kCoincident2) return false;
    const double invLen = 1 / std::sqrt(len2);
    const double dvx = v[ib] - v[ia], dvy = v[ib + 1] - v[ia + 1], dvz = v[ib + 2] - v[ia + 2];
    const double stretchRate = (dvx * dx + dvy * dy + dvz * dz) * invLen;  // m/s
    const double scale = (s.stiffness[k] * (len2 * invLen - s.restLength[k]) + s.damping[k] * stretchRate) * invLen;
    fx = scale * dx, fy = scale * dy, fz = scale * dz;
    return true;
}

/// Spring k's implicit terms into slot i of `out`, scalar (the kernel's formula, for the lanes it cannot load).
inline void springJacobian(const SpringArrays& s, std::uint32_t k, const double* __restrict x,
                           const double* __restrict v, double h, bool first, SpringJacobians& out, std::size_t i) {
    const std::size_t ia = 3 * std::size_t{s.a[k]}, ib = 3 * std::size_t{s.b[k]};
    const double dx = x[ib] - x[ia], dy = x[ib + 1] - x[ia + 1], dz = x[ib + 2] - x[ia + 2];
    const double len2 = dx * dx + dy * dy + dz * dz;
    out.apart[i] = !(len2 < kCoincident2);
    if (!out.apart[i]) return;
    const double len = std::sqrt(len2), inverseLen = 1 / len;
    const double nx = dx * inverseLen, ny = dy * inverseLen, nz = dz * inverseLen;
    const double dvx = v[ib] - v[ia], dvy = v[ib + 1] - v[ia + 1], dvz = v[ib + 2] - v[ia + 2];
    const double ks = s.stiffness[k], kd = s.damping[k], h2ks = h * h * ks;
    const double stretchRate = dvx * nx + dvy * ny + dvz * nz;
    const double alpha = std::max(0.0, 1 - s.restLength[k] * inverseLen);
    const double along =
        h * (ks * (len - s.restLength[k]) + kd * stretchRate) + (first ? h2ks * (1 - alpha) * stretchRate : 0.0);
    const double across = first ? h2ks * alpha : 0.0;
    out.bx[i] = along * nx + across * dvx, out.by[i] = along * ny + across * dvy, out.bz[i] = along * nz + across * dvz;
    out.c0[i] = h2ks * alpha;
    const double scale = std::sqrt(h2ks * (1 - alpha) + h * kd);
    out.ux[i] = scale * nx, out.uy[i] = scale * ny, out.uz[i] = scale * nz;
}

}  // namespace hapticut::physics::kernels
#endif

HWY_BEFORE_NAMESPACE();
namespace hapticut::physics::kernels::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;

// Where vectors hold four doubles, a node's x, y, z (and the next node's x) come in one load and four
// nodes are transposed into coordinate vectors: on an AMD Zen 4 a spring's twelve gathers took more than
// twice as long as these loads and shuffles. Narrower targets gather.
#undef HAPTICUT_SPRING_ROWS
#if HWY_MAX_BYTES >= 32 && HWY_TARGET != HWY_SCALAR
#define HAPTICUT_SPRING_ROWS 1
using D = hn::FixedTag<double, 4>;
#else
#define HAPTICUT_SPRING_ROWS 0
using D = hn::ScalableTag<double>;
#endif
using V = hn::Vec<D>;
using DI64 = hn::RebindToSigned<D>;
constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);

/// The forces of a chunk of springs before they reach the nodes: computed in one pass and added in
/// another, since a pass that did both would stall the vector work on the scalar additions.
struct ChunkForces {
    static constexpr std::size_t kSprings = 256;
    HWY_ALIGN double x[kSprings], y[kSprings], z[kSprings];
    std::uint32_t a[kSprings], b[kSprings];  // the ends of a listed chunk's springs
    bool apart[kSprings];
};

#if HAPTICUT_SPRING_ROWS
/// The coordinates of four nodes (3 i each; none the last node, whose row would read past the array).
HWY_INLINE void LoadNodes(D d, const double* HWY_RESTRICT p, const std::size_t* at, V& x, V& y, V& z) {
    const V r0 = hn::LoadU(d, p + at[0]), r1 = hn::LoadU(d, p + at[1]);
    const V r2 = hn::LoadU(d, p + at[2]), r3 = hn::LoadU(d, p + at[3]);
    const V u0 = hn::InterleaveLower(d, r0, r1), u1 = hn::InterleaveUpper(d, r0, r1);  // x0 x1 z0 z1, y0 y1 . .
    const V u2 = hn::InterleaveLower(d, r2, r3), u3 = hn::InterleaveUpper(d, r2, r3);
    x = hn::ConcatLowerLower(d, u2, u0), y = hn::ConcatLowerLower(d, u3, u1), z = hn::ConcatUpperUpper(d, u2, u0);
}
#else
HWY_INLINE void LoadNodes(D d, const double* HWY_RESTRICT p, const std::size_t* at, V& x, V& y, V& z) {
    const DI64 di64;
    HWY_ALIGN std::int64_t index[kMaxLanes];
    for (std::size_t lane = 0; lane < hn::Lanes(d); ++lane) index[lane] = static_cast<std::int64_t>(at[lane]);
    const auto i = hn::Load(di64, index);
    x = hn::GatherIndex(d, p, i), y = hn::GatherIndex(d, p + 1, i), z = hn::GatherIndex(d, p + 2, i);
}
#endif

/// The rest lengths, stiffnesses and dampings of springs `spring[0..lanes)`: one load each for a run of
/// consecutive springs, gathers otherwise.
HWY_INLINE void LoadConstants(D d, const SpringArrays& s, const std::uint32_t* spring, bool run, V& rest, V& ks,
                              V& kd) {
    if (run) {
        rest = hn::LoadU(d, s.restLength + spring[0]), ks = hn::LoadU(d, s.stiffness + spring[0]);
        kd = hn::LoadU(d, s.damping + spring[0]);
        return;
    }
    HWY_ALIGN std::int64_t index[kMaxLanes];
    for (std::size_t lane = 0; lane < hn::Lanes(d); ++lane) index[lane] = spring[lane];
    const auto i = hn::Load(DI64(), index);
    rest = hn::GatherIndex(d, s.restLength, i), ks = hn::GatherIndex(d, s.stiffness, i);
    kd = hn::GatherIndex(d, s.damping, i);
}

/// The forces of the springs with ends a[0..lanes) and b[0..lanes), `spring` their first index if they
/// are consecutive (`list` null) or listed in `list`, into the chunk from `first` on; the scalar
/// formula's operations in the same order. False if a row of the last node would have been read past
/// the arrays: the caller then takes this group one by one.
HWY_INLINE bool ComputeGroup(const SpringArrays& s, const std::uint32_t* a, const std::uint32_t* b,
                             std::uint32_t spring, const std::uint32_t* list, std::size_t lastNode,
                             const double* HWY_RESTRICT x, const double* HWY_RESTRICT v, ChunkForces& chunk,
                             std::size_t first) {
    const D d;
    const std::size_t lanes = hn::Lanes(d);
    std::size_t at[kMaxLanes], bt[kMaxLanes];
    bool inside = true;
    for (std::size_t lane = 0; lane < lanes; ++lane) {
        at[lane] = 3 * std::size_t{a[lane]}, bt[lane] = 3 * std::size_t{b[lane]};
        inside &= HAPTICUT_SPRING_ROWS == 0 || (a[lane] != lastNode && b[lane] != lastNode);
    }
    if (!inside) return false;
    V xa, ya, za, xb, yb, zb, va, wa, ua, vb, wb, ub;
    LoadNodes(d, x, at, xa, ya, za), LoadNodes(d, x, bt, xb, yb, zb);
    LoadNodes(d, v, at, ua, va, wa), LoadNodes(d, v, bt, ub, vb, wb);
    V rest, ks, kd;
    if (list == nullptr) {
        rest = hn::LoadU(d, s.restLength + spring), ks = hn::LoadU(d, s.stiffness + spring);
        kd = hn::LoadU(d, s.damping + spring);
    } else {
        LoadConstants(d, s, list, false, rest, ks, kd);
    }
    const V dx = hn::Sub(xb, xa), dy = hn::Sub(yb, ya), dz = hn::Sub(zb, za);
    const V len2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
    const auto apart = hn::Not(hn::Lt(len2, hn::Set(d, kCoincident2)));
    const V invLen = hn::Div(hn::Set(d, 1.0), hn::Sqrt(len2));
    const V dvx = hn::Sub(ub, ua), dvy = hn::Sub(vb, va), dvz = hn::Sub(wb, wa);
    const V stretchRate = hn::Mul(hn::Add(hn::Add(hn::Mul(dvx, dx), hn::Mul(dvy, dy)), hn::Mul(dvz, dz)), invLen);
    const V stretch = hn::Sub(hn::Mul(len2, invLen), rest);
    const V scale = hn::Mul(hn::Add(hn::Mul(ks, stretch), hn::Mul(kd, stretchRate)), invLen);
    hn::Store(hn::Mul(scale, dx), d, chunk.x + first), hn::Store(hn::Mul(scale, dy), d, chunk.y + first);
    hn::Store(hn::Mul(scale, dz), d, chunk.z + first);
    if (hn::AllTrue(d, apart)) {
        for (std::size_t lane = 0; lane < lanes; ++lane) chunk.apart[first + lane] = true;
    } else {
        std::uint8_t bits[(kMaxLanes + 7) / 8];
        hn::StoreMaskBits(d, apart, bits);
        for (std::size_t lane = 0; lane < lanes; ++lane) chunk.apart[first + lane] = bits[lane / 8] >> lane % 8 & 1;
    }
    return true;
}

/// Adds a chunk's forces to its springs' ends, in the springs' order. Springs that follow each other
/// with the same end a (the edges' order lists a node's springs to later nodes together) sum onto it
/// in registers and store it once, which leaves the same bits as adding each to memory in turn: only
/// the additions to ends b, which belong to other nodes, go through memory as they come.
HWY_INLINE void AddChunk(const std::uint32_t* HWY_RESTRICT a, const std::uint32_t* HWY_RESTRICT b,
                         const ChunkForces& chunk, std::size_t size, double* HWY_RESTRICT f) {
    for (std::size_t i = 0; i < size;) {
        const std::uint32_t node = a[i];
        double* fa = f + 3 * std::size_t{node};
        double fx = fa[0], fy = fa[1], fz = fa[2];
        for (; i < size && a[i] == node; ++i) {
            if (!chunk.apart[i]) continue;  // also every spring from a node to itself
            fx += chunk.x[i], fy += chunk.y[i], fz += chunk.z[i];
            double* fb = f + 3 * std::size_t{b[i]};
            fb[0] -= chunk.x[i], fb[1] -= chunk.y[i], fb[2] -= chunk.z[i];
        }
        fa[0] = fx, fa[1] = fy, fa[2] = fz;
    }
}

template <bool kListed>
void AddForces(const SpringArrays& s, const std::uint32_t* list, std::size_t count, std::size_t nodeCount,
               const double* HWY_RESTRICT x, const double* HWY_RESTRICT v, double* HWY_RESTRICT f) {
    const std::size_t lanes = hn::Lanes(D());
    const std::size_t lastNode = nodeCount - 1;
    ChunkForces chunk;
    for (std::size_t begin = 0; begin < count; begin += ChunkForces::kSprings) {
        const std::size_t size = std::min(ChunkForces::kSprings, count - begin);
        const std::uint32_t* chunkList = kListed ? list + begin : nullptr;
        if (kListed)
            for (std::size_t i = 0; i < size; ++i) chunk.a[i] = s.a[chunkList[i]], chunk.b[i] = s.b[chunkList[i]];
        const std::uint32_t* a = kListed ? chunk.a : s.a + begin;
        const std::uint32_t* b = kListed ? chunk.b : s.b + begin;
        auto spring = [&](std::size_t i) { return kListed ? chunkList[i] : static_cast<std::uint32_t>(begin + i); };
        std::size_t i = 0;
        for (; i + lanes <= size; i += lanes)
            if (!ComputeGroup(s, a + i, b + i, spring(i), kListed ? chunkList + i : nullptr, lastNode, x, v, chunk, i))
                for (std::size_t j = i; j < i + lanes; ++j)
                    chunk.apart[j] = springForce(s, spring(j), x, v, chunk.x[j], chunk.y[j], chunk.z[j]);
        for (; i < size; ++i) chunk.apart[i] = springForce(s, spring(i), x, v, chunk.x[i], chunk.y[i], chunk.z[i]);
        AddChunk(a, b, chunk, size, f);
    }
}

void AddSpringForces(const SpringArrays& s, std::size_t count, std::size_t nodeCount, const double* HWY_RESTRICT x,
                     const double* HWY_RESTRICT v, double* HWY_RESTRICT f) {
    AddForces<false>(s, nullptr, count, nodeCount, x, v, f);
}

void AddListedSpringForces(const SpringArrays& s, const std::uint32_t* list, std::size_t count, std::size_t nodeCount,
                           const double* HWY_RESTRICT x, const double* HWY_RESTRICT v, double* HWY_RESTRICT f) {
    AddForces<true>(s, list, count, nodeCount, x, v, f);
}

void SpringJacobiansOf(const SpringArrays& s, const std::uint32_t* list, std::size_t count, std::size_t nodeCount,
                       const double* HWY_RESTRICT x, const double* HWY_RESTRICT v, double h, bool first,
                       SpringJacobians& out) {
    const D d;
    const std::size_t lanes = hn::Lanes(d);
    std::size_t i = 0;
    for (; i + lanes <= count; i += lanes) {
        const std::uint32_t* spring = list + i;
        std::size_t at[kMaxLanes], bt[kMaxLanes];
        bool inside = true;
        for (std::size_t lane = 0; lane < lanes; ++lane) {
            const std::uint32_t a = s.a[spring[lane]], b = s.b[spring[lane]];
            at[lane] = 3 * std::size_t{a}, bt[lane] = 3 * std::size_t{b};
            inside &= HAPTICUT_SPRING_ROWS == 0 || (a + 1 < nodeCount && b + 1 < nodeCount);
        }
        if (!inside) {  // a row of the last node would read past the arrays: this group goes one by one
            for (std::size_t lane = 0; lane < lanes; ++lane)
                springJacobian(s, spring[lane], x, v, h, first, out, i + lane);
            continue;
        }
        V xa, ya, za, xb, yb, zb, va, wa, ua, vb, wb, ub;
        LoadNodes(d, x, at, xa, ya, za), LoadNodes(d, x, bt, xb, yb, zb);
        LoadNodes(d, v, at, ua, va, wa), LoadNodes(d, v, bt, ub, vb, wb);
        bool run = true;
        for (std::size_t lane = 1; lane < lanes; ++lane) run &= spring[lane] == spring[0] + lane;
        V rest, ks, kd;
        LoadConstants(d, s, spring, run, rest, ks, kd);
        const V hv = hn::Set(d, h), zero = hn::Zero(d), one = hn::Set(d, 1.0);
        const V dx = hn::Sub(xb, xa), dy = hn::Sub(yb, ya), dz = hn::Sub(zb, za);
        const V len2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
        const auto apart = hn::Not(hn::Lt(len2, hn::Set(d, kCoincident2)));
        const V len = hn::Sqrt(len2);
        const V inverseLen = hn::Div(one, len);
        const V nx = hn::Mul(dx, inverseLen), ny = hn::Mul(dy, inverseLen), nz = hn::Mul(dz, inverseLen);
        const V dvx = hn::Sub(ub, ua), dvy = hn::Sub(vb, va), dvz = hn::Sub(wb, wa);
        const V h2ks = hn::Mul(hn::Mul(hv, hv), ks);
        const V stretchRate = hn::Add(hn::Add(hn::Mul(dvx, nx), hn::Mul(dvy, ny)), hn::Mul(dvz, nz));
        const V alpha = hn::Max(zero, hn::Sub(one, hn::Mul(rest, inverseLen)));
        V along = hn::Mul(hv, hn::Add(hn::Mul(ks, hn::Sub(len, rest)), hn::Mul(kd, stretchRate)));
        const V across = first ? hn::Mul(h2ks, alpha) : zero;
        if (first) along = hn::Add(along, hn::Mul(hn::Mul(h2ks, hn::Sub(one, alpha)), stretchRate));
        hn::Store(hn::Add(hn::Mul(along, nx), hn::Mul(across, dvx)), d, out.bx + i);
        hn::Store(hn::Add(hn::Mul(along, ny), hn::Mul(across, dvy)), d, out.by + i);
        hn::Store(hn::Add(hn::Mul(along, nz), hn::Mul(across, dvz)), d, out.bz + i);
        hn::Store(hn::Mul(h2ks, alpha), d, out.c0 + i);
        const V scale = hn::Sqrt(hn::Add(hn::Mul(h2ks, hn::Sub(one, alpha)), hn::Mul(hv, kd)));
        hn::Store(hn::Mul(scale, nx), d, out.ux + i), hn::Store(hn::Mul(scale, ny), d, out.uy + i);
        hn::Store(hn::Mul(scale, nz), d, out.uz + i);
        std::uint8_t bits[(kMaxLanes + 7) / 8];
        hn::StoreMaskBits(d, apart, bits);
        for (std::size_t lane = 0; lane < lanes; ++lane) out.apart[i + lane] = bits[lane / 8] >> lane % 8 & 1;
    }
    for (; i < count; ++i) springJacobian(s, list[i], x, v, h, first, out, i);
}

void InvertRowBlocks(const SystemRows& a, SymmetricBlocks& inverse, std::size_t first, std::size_t end) {
    // Every target's lanes divide a slice; the full-width tag's, which may be wider than the forces'.
    using DF = hn::ScalableTag<double>;
    const DF d;
    const hn::Rebind<float, DF> df;
    const std::size_t lanes = hn::Lanes(d);
    const SlicedCouplings& c = *a.couplings;
    const SymmetricBlocks& r = *a.toResting;
    auto widened = [&](const std::vector<float>& v, std::size_t at) { return hn::PromoteTo(d, hn::LoadU(df, &v[at])); };
    for (std::size_t slice = first / kSliceRows; slice * kSliceRows < end; ++slice) {
        const std::size_t begin = c.sliceBegin[slice];
        const std::size_t width = (c.sliceBegin[slice + 1] - begin) / kSliceRows;
        for (std::size_t group = 0; group < kSliceRows; group += lanes) {
            const std::size_t row = slice * kSliceRows + group;
            const auto diagonal = hn::LoadU(d, a.diagonal + row);
            auto xx = hn::Add(diagonal, widened(r.xx, row)), xy = widened(r.xy, row), xz = widened(r.xz, row);
            auto yy = hn::Add(diagonal, widened(r.yy, row)), yz = widened(r.yz, row);
            auto zz = hn::Add(diagonal, widened(r.zz, row));
            for (std::size_t j = 0; j < width; ++j) {
                const std::size_t slot = begin + j * kSliceRows + group;
                const auto c0 = widened(c.c0, slot), ux = widened(c.ux, slot);
                const auto uy = widened(c.uy, slot), uz = widened(c.uz, slot);
                xx = hn::Add(xx, hn::Add(c0, hn::Mul(ux, ux))), xy = hn::Add(xy, hn::Mul(ux, uy));
                xz = hn::Add(xz, hn::Mul(ux, uz));
                yy = hn::Add(yy, hn::Add(c0, hn::Mul(uy, uy))), yz = hn::Add(yz, hn::Mul(uy, uz));
                zz = hn::Add(zz, hn::Add(c0, hn::Mul(uz, uz)));
            }
            const auto cxx = hn::Sub(hn::Mul(yy, zz), hn::Mul(yz, yz));
            const auto cxy = hn::Sub(hn::Mul(xz, yz), hn::Mul(xy, zz));
            const auto cxz = hn::Sub(hn::Mul(xy, yz), hn::Mul(xz, yy));
            const auto det = hn::Add(hn::Add(hn::Mul(xx, cxx), hn::Mul(xy, cxy)), hn::Mul(xz, cxz));
            // A row without a diagonal (pinned, or padding) is left out of the solve: a zero block.
            const auto inverseDet = hn::IfThenZeroElse(hn::Eq(diagonal, hn::Zero(d)), hn::Div(hn::Set(d, 1.0), det));
            auto store = [&](hn::Vec<DF> value, std::vector<float>& v) {
                hn::StoreU(hn::DemoteTo(df, hn::Mul(value, inverseDet)), df, &v[row]);
            };
            store(cxx, inverse.xx), store(cxy, inverse.xy), store(cxz, inverse.xz);
            store(hn::Sub(hn::Mul(xx, zz), hn::Mul(xz, xz)), inverse.yy);
            store(hn::Sub(hn::Mul(xy, xz), hn::Mul(xx, yz)), inverse.yz);
            store(hn::Sub(hn::Mul(xx, yy), hn::Mul(xy, xy)), inverse.zz);
        }
    }
}

}  // namespace hapticut::physics::kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace hapticut::physics::kernels {

HWY_EXPORT(AddSpringForces);
HWY_EXPORT(AddListedSpringForces);
HWY_EXPORT(SpringJacobiansOf);
HWY_EXPORT(InvertRowBlocks);

void addSpringForces(const SpringArrays& springs, std::size_t count, std::size_t nodes, const double* x,
                     const double* v, double* f) {
    HWY_DYNAMIC_DISPATCH(AddSpringForces)(springs, count, nodes, x, v, f);
}

void addListedSpringForces(const SpringArrays& springs, const std::uint32_t* list, std::size_t count, std::size_t nodes,
                           const double* x, const double* v, double* f) {
    HWY_DYNAMIC_DISPATCH(AddListedSpringForces)(springs, list, count, nodes, x, v, f);
}

void springJacobians(const SpringArrays& springs, const std::uint32_t* list, std::size_t count, std::size_t nodes,
                     const double* x, const double* v, double h, bool firstLinearisation, SpringJacobians& out) {
    HWY_DYNAMIC_DISPATCH(SpringJacobiansOf)(springs, list, count, nodes, x, v, h, firstLinearisation, out);
}

void invertRowBlocks(const SystemRows& rows, SymmetricBlocks& inverse, RowRange range) {
    HWY_DYNAMIC_DISPATCH(InvertRowBlocks)(rows, inverse, range.first, range.end);
}

}  // namespace hapticut::physics::kernels
#endif
