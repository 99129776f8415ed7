// The springs' forces, and their Jacobians for the implicit step, as SIMD kernels: this file is compiled
// once per target by Highway's foreach_target, and the HWY_ONCE part at the end dispatches to the best
// one the machine supports (solver_kernels.cpp's forceTarget chooses for both files).
//
// A spring's force takes a square root, a division and some thirty products, which the vector lanes
// share; it then reaches its two ends' force rows (ForceRow: four doubles, one vector) a spring at a
// time, in the springs' order, so that no two lanes ever add to the same node at once. The arithmetic
// is the scalar formula's, operation for operation and without fused multiply-adds (CMakeLists.txt
// compiles this file with -ffp-contract=off), so every target gives the scalar loop's forces to the bit
// and a golden force trace does not depend on the machine.
//
// Tried and not kept (Intel Xeon, Sapphire Rapids class, 9,714 heart): computing a chunk of rows first
// and adding them in a pass of their own, and summing a run of springs with the same end a in a
// register, each cost more than they saved (4.8 and 3.8 ns a spring against 3.5): their branches on
// where a run ends mispredict, and the scattered additions were not what bound the loop. Neither were
// the square root and division; the instructions a spring takes are. Eight springs a vector on AVX-512,
// their halves combined into 512-bit vectors, took 4.1-4.2 ns against 3.1.
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

// Where vectors hold four doubles, a node's coordinates come in two 16-byte loads and four springs'
// differences are shuffled into coordinate vectors (LoadDifferences): on an AMD Zen 4 a spring's twelve
// gathers took more than twice as long as loads and shuffles. Narrower targets gather.
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

/// Adds a spring's force to its ends: +f to a, -f to b.
HWY_INLINE void AddToEnds(double fx, double fy, double fz, std::uint32_t a, std::uint32_t b, ForceRow* HWY_RESTRICT f) {
    f[a].x += fx, f[a].y += fy, f[a].z += fz;
    f[b].x -= fx, f[b].y -= fy, f[b].z -= fz;
}

#if HAPTICUT_SPRING_ROWS
using D2 = hn::Half<D>;

/// The differences p_b - p_a of four springs' ends as coordinate vectors, from half rows: a node's x and
/// y in one 16-byte load, its y and z in another (which never reads past the last node), two springs'
/// halves to a vector. Three shuffles then put them in coordinate order, where transposing whole rows
/// took fourteen.
HWY_INLINE void LoadDifferences(const double* HWY_RESTRICT p, const std::size_t* at, const std::size_t* bt, V& dx,
                                V& dy, V& dz) {
    const D d;
    const D2 d2;
    auto pair = [&](const std::size_t* t, std::size_t lo, std::size_t hi, std::size_t offset) {
        return hn::Combine(d, hn::LoadU(d2, p + t[hi] + offset), hn::LoadU(d2, p + t[lo] + offset));
    };
    const V xy02 = hn::Sub(pair(bt, 0, 2, 0), pair(at, 0, 2, 0));  // dx0 dy0 | dx2 dy2
    const V xy13 = hn::Sub(pair(bt, 1, 3, 0), pair(at, 1, 3, 0));
    const V yz02 = hn::Sub(pair(bt, 0, 2, 1), pair(at, 0, 2, 1));  // . dz0 | . dz2
    const V yz13 = hn::Sub(pair(bt, 1, 3, 1), pair(at, 1, 3, 1));
    dx = hn::InterleaveLower(d, xy02, xy13), dy = hn::InterleaveUpper(d, xy02, xy13);
    dz = hn::InterleaveUpper(d, yz02, yz13);
}

/// Four springs' forces to their ends in the springs' order, skipping those whose bit in `apart` (a
/// mask's bits, StoreMaskBits) is clear.
HWY_INLINE void AddGroup(V fx, V fy, V fz, const std::uint32_t* a, const std::uint32_t* b, const std::uint8_t* apart,
                         ForceRow* HWY_RESTRICT f) {
    const D d;
    const V xy02 = hn::InterleaveLower(d, fx, fy), xy13 = hn::InterleaveUpper(d, fx, fy);  // fx0 fy0 | fx2 fy2
    const V zero = hn::Zero(d);
    const V z02 = hn::InterleaveLower(d, fz, zero), z13 = hn::InterleaveUpper(d, fz, zero);  // fz0 0 | fz2 0
    const V rows[4] = {hn::ConcatLowerLower(d, z02, xy02), hn::ConcatLowerLower(d, z13, xy13),
                       hn::ConcatUpperUpper(d, z02, xy02), hn::ConcatUpperUpper(d, z13, xy13)};
    const bool all = (apart[0] & 0xF) == 0xF;  // nearly always: coincident ends come only from a fresh cut
    for (std::size_t lane = 0; lane < 4; ++lane) {
        if (!all && !(apart[0] >> lane & 1)) continue;
        double* fa = &f[a[lane]].x;
        hn::Store(hn::Add(hn::Load(d, fa), rows[lane]), d, fa);
        double* fb = &f[b[lane]].x;
        hn::Store(hn::Sub(hn::Load(d, fb), rows[lane]), d, fb);
    }
}
#else
/// The coordinates of a vector of nodes (3 i each), gathered.
HWY_INLINE void LoadNodes(D d, const double* HWY_RESTRICT p, const std::size_t* at, V& x, V& y, V& z) {
    const DI64 di64;
    HWY_ALIGN std::int64_t index[kMaxLanes];
    for (std::size_t lane = 0; lane < hn::Lanes(d); ++lane) index[lane] = static_cast<std::int64_t>(at[lane]);
    const auto i = hn::Load(di64, index);
    x = hn::GatherIndex(d, p, i), y = hn::GatherIndex(d, p + 1, i), z = hn::GatherIndex(d, p + 2, i);
}

HWY_INLINE void LoadDifferences(const double* HWY_RESTRICT p, const std::size_t* at, const std::size_t* bt, V& dx,
                                V& dy, V& dz) {
    const D d;
    V xa, ya, za, xb, yb, zb;
    LoadNodes(d, p, at, xa, ya, za), LoadNodes(d, p, bt, xb, yb, zb);
    dx = hn::Sub(xb, xa), dy = hn::Sub(yb, ya), dz = hn::Sub(zb, za);
}

HWY_INLINE void AddGroup(V fx, V fy, V fz, const std::uint32_t* a, const std::uint32_t* b, const std::uint8_t* apart,
                         ForceRow* HWY_RESTRICT f) {
    const D d;
    HWY_ALIGN double x[kMaxLanes], y[kMaxLanes], z[kMaxLanes];
    hn::Store(fx, d, x), hn::Store(fy, d, y), hn::Store(fz, d, z);
    for (std::size_t lane = 0; lane < hn::Lanes(d); ++lane)
        if (apart[lane / 8] >> lane % 8 & 1) AddToEnds(x[lane], y[lane], z[lane], a[lane], b[lane], f);
}
#endif

/// Spring k's force to its ends, scalar (for the springs no whole vector takes).
HWY_INLINE void AddOne(const SpringArrays& s, std::uint32_t k, const double* HWY_RESTRICT x,
                       const double* HWY_RESTRICT v, ForceRow* HWY_RESTRICT f) {
    double fx, fy, fz;
    if (springForce(s, k, x, v, fx, fy, fz)) AddToEnds(fx, fy, fz, s.a[k], s.b[k], f);
}

/// The springs' forces a vector of springs at a time, the scalar formula's operations in its order, each
/// added to its ends before the next spring's: listed springs, or [0, count) when `list` is null.
template <bool kListed>
void AddForces(const SpringArrays& s, const std::uint32_t* list, std::size_t count, const double* HWY_RESTRICT x,
               const double* HWY_RESTRICT v, ForceRow* HWY_RESTRICT f) {
    const D d;
    const std::size_t lanes = hn::Lanes(d);
    auto spring = [&](std::size_t i) { return kListed ? list[i] : static_cast<std::uint32_t>(i); };
    const SpringArrays springs = s;  // a copy the stores to f cannot alias, so its pointers stay in registers
    std::size_t i = 0;
    for (; i + lanes <= count; i += lanes) {
        std::uint32_t a[kMaxLanes], b[kMaxLanes];
        std::size_t at[kMaxLanes], bt[kMaxLanes];
        for (std::size_t lane = 0; lane < lanes; ++lane) {
            const std::uint32_t k = spring(i + lane);
            a[lane] = springs.a[k], b[lane] = springs.b[k];
            at[lane] = 3 * std::size_t{a[lane]}, bt[lane] = 3 * std::size_t{b[lane]};
        }
        V dx, dy, dz, dvx, dvy, dvz;
        LoadDifferences(x, at, bt, dx, dy, dz), LoadDifferences(v, at, bt, dvx, dvy, dvz);
        V rest, ks, kd;
        if (kListed) {
            bool consecutive = true;
            for (std::size_t lane = 1; lane < lanes; ++lane) consecutive &= list[i + lane] == list[i] + lane;
            LoadConstants(d, springs, list + i, consecutive, rest, ks, kd);
        } else {
            rest = hn::LoadU(d, springs.restLength + i), ks = hn::LoadU(d, springs.stiffness + i);
            kd = hn::LoadU(d, springs.damping + i);
        }
        const V len2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
        const auto apart = hn::Not(hn::Lt(len2, hn::Set(d, kCoincident2)));
        const V invLen = hn::Div(hn::Set(d, 1.0), hn::Sqrt(len2));
        const V stretchRate = hn::Mul(hn::Add(hn::Add(hn::Mul(dvx, dx), hn::Mul(dvy, dy)), hn::Mul(dvz, dz)), invLen);
        const V stretch = hn::Sub(hn::Mul(len2, invLen), rest);
        const V scale = hn::Mul(hn::Add(hn::Mul(ks, stretch), hn::Mul(kd, stretchRate)), invLen);
        std::uint8_t bits[(kMaxLanes + 7) / 8] = {};
        hn::StoreMaskBits(d, apart, bits);
        AddGroup(hn::Mul(scale, dx), hn::Mul(scale, dy), hn::Mul(scale, dz), a, b, bits, f);
    }
    for (; i < count; ++i) AddOne(springs, spring(i), x, v, f);
}

void AddSpringForces(const SpringArrays& s, std::size_t count, const double* HWY_RESTRICT x,
                     const double* HWY_RESTRICT v, ForceRow* HWY_RESTRICT f) {
    AddForces<false>(s, nullptr, count, x, v, f);
}

void AddListedSpringForces(const SpringArrays& s, const std::uint32_t* list, std::size_t count,
                           const double* HWY_RESTRICT x, const double* HWY_RESTRICT v, ForceRow* HWY_RESTRICT f) {
    AddForces<true>(s, list, count, x, v, f);
}

void SpringJacobiansOf(const SpringArrays& s, const std::uint32_t* list, std::size_t count,
                       const double* HWY_RESTRICT x, const double* HWY_RESTRICT v, double h, bool first,
                       SpringJacobians& out) {
    const D d;
    const std::size_t lanes = hn::Lanes(d);
    std::size_t i = 0;
    for (; i + lanes <= count; i += lanes) {
        const std::uint32_t* spring = list + i;
        std::size_t at[kMaxLanes], bt[kMaxLanes];
        for (std::size_t lane = 0; lane < lanes; ++lane)
            at[lane] = 3 * std::size_t{s.a[spring[lane]]}, bt[lane] = 3 * std::size_t{s.b[spring[lane]]};
        V dx, dy, dz, dvx, dvy, dvz;
        LoadDifferences(x, at, bt, dx, dy, dz), LoadDifferences(v, at, bt, dvx, dvy, dvz);
        bool run = true;
        for (std::size_t lane = 1; lane < lanes; ++lane) run &= spring[lane] == spring[0] + lane;
        V rest, ks, kd;
        LoadConstants(d, s, spring, run, rest, ks, kd);
        const V hv = hn::Set(d, h), zero = hn::Zero(d), one = hn::Set(d, 1.0);
        const V len2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
        const auto apart = hn::Not(hn::Lt(len2, hn::Set(d, kCoincident2)));
        const V len = hn::Sqrt(len2);
        const V inverseLen = hn::Div(one, len);
        const V nx = hn::Mul(dx, inverseLen), ny = hn::Mul(dy, inverseLen), nz = hn::Mul(dz, inverseLen);
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

void addSpringForces(const SpringArrays& springs, std::size_t count, const double* x, const double* v, ForceRow* f) {
    HWY_DYNAMIC_DISPATCH(AddSpringForces)(springs, count, x, v, f);
}

void addSpringForcesOn(const SpringArrays& springs, std::uint32_t node, const std::uint32_t* list, std::size_t count,
                       const double* x, const double* v, double* f) {
    for (std::size_t e = 0; e < count; ++e) {
        double fx, fy, fz;
        if (!springForce(springs, list[e], x, v, fx, fy, fz)) continue;
        const double sign = springs.a[list[e]] == node ? 1.0 : -1.0;
        f[0] += sign * fx, f[1] += sign * fy, f[2] += sign * fz;
    }
}

void addListedSpringForces(const SpringArrays& springs, const std::uint32_t* list, std::size_t count, const double* x,
                           const double* v, ForceRow* f) {
    HWY_DYNAMIC_DISPATCH(AddListedSpringForces)(springs, list, count, x, v, f);
}

void springJacobians(const SpringArrays& springs, const std::uint32_t* list, std::size_t count, const double* x,
                     const double* v, double h, bool firstLinearisation, SpringJacobians& out) {
    HWY_DYNAMIC_DISPATCH(SpringJacobiansOf)(springs, list, count, x, v, h, firstLinearisation, out);
}

void invertRowBlocks(const SystemRows& rows, SymmetricBlocks& inverse, RowRange range) {
    HWY_DYNAMIC_DISPATCH(InvertRowBlocks)(rows, inverse, range.first, range.end);
}

}  // namespace hapticut::physics::kernels
#endif
