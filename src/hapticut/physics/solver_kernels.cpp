// The implicit solve's SIMD kernels: this file is compiled once per target by Highway's foreach_target,
// and the HWY_ONCE part at the end dispatches to the best one the machine supports.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "hapticut/physics/solver_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <string_view>

#include "hapticut/physics/solver_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace hapticut::physics::kernels::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;
using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;

/// Single-precision entries widened to double lanes.
HWY_INLINE V loadFloats(D d, const float* p) { return hn::PromoteTo(d, hn::LoadU(hn::Rebind<float, D>(), p)); }

/// The symmetric block m times (rx, ry, rz), for the rows at `at`.
HWY_INLINE void symmetricTimes(D d, const SymmetricBlocks& m, std::size_t at, V rx, V ry, V rz, V& ox, V& oy, V& oz) {
    const V xx = loadFloats(d, m.xx.data() + at), xy = loadFloats(d, m.xy.data() + at);
    const V xz = loadFloats(d, m.xz.data() + at), yy = loadFloats(d, m.yy.data() + at);
    const V yz = loadFloats(d, m.yz.data() + at), zz = loadFloats(d, m.zz.data() + at);
    ox = hn::MulAdd(xx, rx, hn::MulAdd(xy, ry, hn::Mul(xz, rz)));
    oy = hn::MulAdd(xy, rx, hn::MulAdd(yy, ry, hn::Mul(yz, rz)));
    oz = hn::MulAdd(xz, rx, hn::MulAdd(yz, ry, hn::Mul(zz, rz)));
}

/// A pass's running sums, lane by lane, over rows with residual r and preconditioned residual z: |r|²,
/// r·z and the largest |r_i|² of a row.
HWY_INLINE void addToSums(V rx, V ry, V rzv, V zx, V zy, V zz, V& r2, V& rz, V& rowMax2) {
    r2 = hn::MulAdd(rx, rx, hn::MulAdd(ry, ry, hn::MulAdd(rzv, rzv, r2)));
    rz = hn::MulAdd(rx, zx, hn::MulAdd(ry, zy, hn::MulAdd(rzv, zz, rz)));
    rowMax2 = hn::Max(rowMax2, hn::MulAdd(rx, rx, hn::MulAdd(ry, ry, hn::Mul(rzv, rzv))));
}

/// The running sums' lanes combined.
HWY_INLINE Sums totalOf(D d, V r2, V rz, V rowMax2) {
    return {hn::GetLane(hn::SumOfLanes(d, r2)), hn::GetLane(hn::SumOfLanes(d, rz)),
            hn::GetLane(hn::MaxOfLanes(d, rowMax2))};
}

#if HWY_TARGET == HWY_AVX2
/// The entries of y at the rows `other[0..4)`, one load each: on an AMD Zen 3 (EPYC) the product's three
/// gathers a slot took twice as long as these twelve loads (two to a half, the halves joined). Highway's
/// single-lane sets and interleaves for the same cost a tenth more at 10,000 triangles.
HWY_INLINE void LoadOthers(D, const Field& y, const std::int32_t* HWY_RESTRICT other, V& ox, V& oy, V& oz) {
    auto four = [&](const double* HWY_RESTRICT p) {
        return V{_mm256_set_pd(p[other[3]], p[other[2]], p[other[1]], p[other[0]])};
    };
    ox = four(y.x.data()), oy = four(y.y.data()), oz = four(y.z.data());
}
#elif HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
/// The same with eight lanes, two halves of four loads joined: on an AMD Zen 5 the three gathers a slot
/// took longer than the whole product on AVX2.
HWY_INLINE void LoadOthers(D, const Field& y, const std::int32_t* HWY_RESTRICT other, V& ox, V& oy, V& oz) {
    auto eight = [&](const double* HWY_RESTRICT p) {
        const __m256d lo = _mm256_set_pd(p[other[3]], p[other[2]], p[other[1]], p[other[0]]);
        const __m256d hi = _mm256_set_pd(p[other[7]], p[other[6]], p[other[5]], p[other[4]]);
        return V{_mm512_insertf64x4(_mm512_castpd256_pd512(lo), hi, 1)};
    };
    ox = eight(y.x.data()), oy = eight(y.y.data()), oz = eight(y.z.data());
}
#else
/// The entries of y at the rows `other[0..lanes)`, gathered.
HWY_INLINE void LoadOthers(D d, const Field& y, const std::int32_t* HWY_RESTRICT other, V& ox, V& oy, V& oz) {
    const auto index = hn::PromoteTo(hn::Rebind<std::int64_t, D>(), hn::LoadU(hn::Rebind<std::int32_t, D>(), other));
    ox = hn::GatherIndex(d, y.x.data(), index), oy = hn::GatherIndex(d, y.y.data(), index);
    oz = hn::GatherIndex(d, y.z.data(), index);
}
#endif

double Multiply(const SystemRows& a, const Field& y, Field& out, std::size_t first, std::size_t end) {
    const D d;
    const std::size_t lanes = hn::Lanes(d);
    const SlicedCouplings& c = *a.couplings;
    V yAy = hn::Zero(d);
    for (std::size_t slice = first / kSliceRows; slice * kSliceRows < end; ++slice) {
        const std::size_t begin = c.sliceBegin[slice];
        const std::size_t width = (c.sliceBegin[slice + 1] - begin) / kSliceRows;
        for (std::size_t group = 0; group < kSliceRows; group += lanes) {
            const std::size_t row = slice * kSliceRows + group;
            const V yx = hn::LoadU(d, y.x.data() + row), yy = hn::LoadU(d, y.y.data() + row);
            const V yz = hn::LoadU(d, y.z.data() + row);
            // Each row's sum builds up in registers, gathering its neighbours' y; nothing is scattered.
            V sx = hn::Zero(d), sy = hn::Zero(d), sz = hn::Zero(d);
            if (a.anyResting) symmetricTimes(d, *a.toResting, row, yx, yy, yz, sx, sy, sz);
            const V diag = hn::LoadU(d, a.diagonal + row);
            sx = hn::MulAdd(diag, yx, sx), sy = hn::MulAdd(diag, yy, sy), sz = hn::MulAdd(diag, yz, sz);
            for (std::size_t j = 0; j < width; ++j) {
                const std::size_t slot = begin + j * kSliceRows + group;
                V ox, oy, oz;
                LoadOthers(d, y, c.other.data() + slot, ox, oy, oz);
                const V dx = hn::Sub(yx, ox), dy = hn::Sub(yy, oy), dz = hn::Sub(yz, oz);
                const V c0 = loadFloats(d, c.c0.data() + slot), ux = loadFloats(d, c.ux.data() + slot);
                const V uy = loadFloats(d, c.uy.data() + slot), uz = loadFloats(d, c.uz.data() + slot);
                const V along = hn::MulAdd(ux, dx, hn::MulAdd(uy, dy, hn::Mul(uz, dz)));
                sx = hn::MulAdd(c0, dx, hn::MulAdd(along, ux, sx));
                sy = hn::MulAdd(c0, dy, hn::MulAdd(along, uy, sy));
                sz = hn::MulAdd(c0, dz, hn::MulAdd(along, uz, sz));
            }
            hn::StoreU(sx, d, out.x.data() + row), hn::StoreU(sy, d, out.y.data() + row);
            hn::StoreU(sz, d, out.z.data() + row);
            yAy = hn::MulAdd(yx, sx, hn::MulAdd(yy, sy, hn::MulAdd(yz, sz, yAy)));
        }
    }
    return hn::GetLane(hn::SumOfLanes(d, yAy));
}

void BlockProduct(const BlockRows& a, const Field& y, const Field* b, Field& out, std::size_t first, std::size_t end) {
    const D d;
    const std::size_t lanes = hn::Lanes(d);
    const SlicedBlocks& c = *a.couplings;
    const SymmetricBlocks& m = c.blocks;
    for (std::size_t slice = first / kSliceRows; slice * kSliceRows < end; ++slice) {
        const std::size_t begin = c.sliceBegin[slice];
        const std::size_t width = (c.sliceBegin[slice + 1] - begin) / kSliceRows;
        for (std::size_t group = 0; group < kSliceRows; group += lanes) {
            const std::size_t row = slice * kSliceRows + group;
            V sx, sy, sz;
            symmetricTimes(d, *a.diagonal, row, hn::LoadU(d, y.x.data() + row), hn::LoadU(d, y.y.data() + row),
                           hn::LoadU(d, y.z.data() + row), sx, sy, sz);
            for (std::size_t j = 0; j < width; ++j) {
                const std::size_t slot = begin + j * kSliceRows + group;
                V ox, oy, oz;
                LoadOthers(d, y, c.other.data() + slot, ox, oy, oz);
                // A block's product summed apart, then added: the row's sums wait on one addition a slot.
                V tx, ty, tz;
                symmetricTimes(d, m, slot, ox, oy, oz, tx, ty, tz);
                sx = hn::Add(sx, tx), sy = hn::Add(sy, ty), sz = hn::Add(sz, tz);
            }
            if (b) {
                sx = hn::Sub(hn::LoadU(d, b->x.data() + row), sx);
                sy = hn::Sub(hn::LoadU(d, b->y.data() + row), sy);
                sz = hn::Sub(hn::LoadU(d, b->z.data() + row), sz);
            }
            hn::StoreU(sx, d, out.x.data() + row), hn::StoreU(sy, d, out.y.data() + row);
            hn::StoreU(sz, d, out.z.data() + row);
        }
    }
}

Sums StartPass(std::size_t first, std::size_t end, const Field& b, const Field& product, const SymmetricBlocks& inverse,
               Field& r, Field& z, Field& p, double omega) {
    const D d;
    const V w = hn::Set(d, omega);  // times 1 leaves z as it was, bit for bit
    V r2 = hn::Zero(d), rz = hn::Zero(d), rowMax2 = hn::Zero(d);
    for (std::size_t i = first; i < end; i += hn::Lanes(d)) {
        const V rx = hn::Sub(hn::LoadU(d, b.x.data() + i), hn::LoadU(d, product.x.data() + i));
        const V ry = hn::Sub(hn::LoadU(d, b.y.data() + i), hn::LoadU(d, product.y.data() + i));
        const V rzv = hn::Sub(hn::LoadU(d, b.z.data() + i), hn::LoadU(d, product.z.data() + i));
        V zx, zy, zz;
        symmetricTimes(d, inverse, i, rx, ry, rzv, zx, zy, zz);
        zx = hn::Mul(w, zx), zy = hn::Mul(w, zy), zz = hn::Mul(w, zz);
        hn::StoreU(rx, d, r.x.data() + i), hn::StoreU(ry, d, r.y.data() + i), hn::StoreU(rzv, d, r.z.data() + i);
        hn::StoreU(zx, d, z.x.data() + i), hn::StoreU(zy, d, z.y.data() + i), hn::StoreU(zz, d, z.z.data() + i);
        hn::StoreU(zx, d, p.x.data() + i), hn::StoreU(zy, d, p.y.data() + i), hn::StoreU(zz, d, p.z.data() + i);
        addToSums(rx, ry, rzv, zx, zy, zz, r2, rz, rowMax2);
    }
    return totalOf(d, r2, rz, rowMax2);
}

Sums UpdatePass(std::size_t first, std::size_t end, double alpha, const Field& p, const Field& q,
                const SymmetricBlocks& inverse, Field& x, Field& r, Field& z, double omega) {
    const D d;
    const V a = hn::Set(d, alpha), minusA = hn::Set(d, -alpha), w = hn::Set(d, omega);
    V r2 = hn::Zero(d), rz = hn::Zero(d), rowMax2 = hn::Zero(d);
    for (std::size_t i = first; i < end; i += hn::Lanes(d)) {
        hn::StoreU(hn::MulAdd(a, hn::LoadU(d, p.x.data() + i), hn::LoadU(d, x.x.data() + i)), d, x.x.data() + i);
        hn::StoreU(hn::MulAdd(a, hn::LoadU(d, p.y.data() + i), hn::LoadU(d, x.y.data() + i)), d, x.y.data() + i);
        hn::StoreU(hn::MulAdd(a, hn::LoadU(d, p.z.data() + i), hn::LoadU(d, x.z.data() + i)), d, x.z.data() + i);
        const V rx = hn::MulAdd(minusA, hn::LoadU(d, q.x.data() + i), hn::LoadU(d, r.x.data() + i));
        const V ry = hn::MulAdd(minusA, hn::LoadU(d, q.y.data() + i), hn::LoadU(d, r.y.data() + i));
        const V rzv = hn::MulAdd(minusA, hn::LoadU(d, q.z.data() + i), hn::LoadU(d, r.z.data() + i));
        V zx, zy, zz;
        symmetricTimes(d, inverse, i, rx, ry, rzv, zx, zy, zz);
        zx = hn::Mul(w, zx), zy = hn::Mul(w, zy), zz = hn::Mul(w, zz);
        hn::StoreU(rx, d, r.x.data() + i), hn::StoreU(ry, d, r.y.data() + i), hn::StoreU(rzv, d, r.z.data() + i);
        hn::StoreU(zx, d, z.x.data() + i), hn::StoreU(zy, d, z.y.data() + i), hn::StoreU(zz, d, z.z.data() + i);
        addToSums(rx, ry, rzv, zx, zy, zz, r2, rz, rowMax2);
    }
    return totalOf(d, r2, rz, rowMax2);
}

void DirectionPass(std::size_t first, std::size_t end, double beta, const Field& z, Field& p) {
    const D d;
    const V b = hn::Set(d, beta);
    for (std::size_t i = first; i < end; i += hn::Lanes(d)) {
        hn::StoreU(hn::MulAdd(b, hn::LoadU(d, p.x.data() + i), hn::LoadU(d, z.x.data() + i)), d, p.x.data() + i);
        hn::StoreU(hn::MulAdd(b, hn::LoadU(d, p.y.data() + i), hn::LoadU(d, z.y.data() + i)), d, p.y.data() + i);
        hn::StoreU(hn::MulAdd(b, hn::LoadU(d, p.z.data() + i), hn::LoadU(d, z.z.data() + i)), d, p.z.data() + i);
    }
}

Sums SmoothPass(std::size_t first, std::size_t end, double omega, const Field& r, const Field* product,
                const SymmetricBlocks& inverse, Field& z) {
    const D d;
    const V w = hn::Set(d, omega);
    V r2 = hn::Zero(d), rz = hn::Zero(d), rowMax2 = hn::Zero(d);
    for (std::size_t i = first; i < end; i += hn::Lanes(d)) {
        const V rx = hn::LoadU(d, r.x.data() + i), ry = hn::LoadU(d, r.y.data() + i);
        const V rzv = hn::LoadU(d, r.z.data() + i);
        V sx = rx, sy = ry, sz = rzv, zx = hn::Zero(d), zy = hn::Zero(d), zz = hn::Zero(d);
        if (product) {
            sx = hn::Sub(rx, hn::LoadU(d, product->x.data() + i)),
            sy = hn::Sub(ry, hn::LoadU(d, product->y.data() + i));
            sz = hn::Sub(rzv, hn::LoadU(d, product->z.data() + i));
            zx = hn::LoadU(d, z.x.data() + i), zy = hn::LoadU(d, z.y.data() + i), zz = hn::LoadU(d, z.z.data() + i);
        }
        V cx, cy, cz;
        symmetricTimes(d, inverse, i, sx, sy, sz, cx, cy, cz);
        zx = hn::MulAdd(w, cx, zx), zy = hn::MulAdd(w, cy, zy), zz = hn::MulAdd(w, cz, zz);
        hn::StoreU(zx, d, z.x.data() + i), hn::StoreU(zy, d, z.y.data() + i), hn::StoreU(zz, d, z.z.data() + i);
        addToSums(rx, ry, rzv, zx, zy, zz, r2, rz, rowMax2);
    }
    return totalOf(d, r2, rz, rowMax2);
}

}  // namespace hapticut::physics::kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace hapticut::physics::kernels {

namespace {
std::int64_t forcedTarget = 0;  // forceTarget's choice; zero when the kernels run with the best
}  // namespace

HWY_EXPORT(Multiply);
HWY_EXPORT(BlockProduct);
HWY_EXPORT(StartPass);
HWY_EXPORT(UpdatePass);
HWY_EXPORT(DirectionPass);
HWY_EXPORT(SmoothPass);

double multiply(const SystemRows& a, const Field& y, Field& out, RowRange range) {
    return HWY_DYNAMIC_DISPATCH(Multiply)(a, y, out, range.first, range.end);
}

void blockProduct(const BlockRows& a, const Field& y, const Field* b, Field& out, RowRange range) {
    HWY_DYNAMIC_DISPATCH(BlockProduct)(a, y, b, out, range.first, range.end);
}

Sums startPass(RowRange range, const Field& b, const Field& product, const SymmetricBlocks& inverse, Field& r, Field& z,
               Field& p, double omega) {
    return HWY_DYNAMIC_DISPATCH(StartPass)(range.first, range.end, b, product, inverse, r, z, p, omega);
}

Sums updatePass(RowRange range, double alpha, const Field& p, const Field& q, const SymmetricBlocks& inverse, Field& x,
                Field& r, Field& z, double omega) {
    return HWY_DYNAMIC_DISPATCH(UpdatePass)(range.first, range.end, alpha, p, q, inverse, x, r, z, omega);
}

void directionPass(RowRange range, double beta, const Field& z, Field& p) {
    HWY_DYNAMIC_DISPATCH(DirectionPass)(range.first, range.end, beta, z, p);
}

Sums smoothPass(RowRange range, double omega, const Field& r, const Field* product, const SymmetricBlocks& inverse,
                Field& z) {
    return HWY_DYNAMIC_DISPATCH(SmoothPass)(range.first, range.end, omega, r, product, inverse, z);
}

const char* targetName() {
    const std::int64_t available = hwy::SupportedTargets() & HWY_TARGETS;
    return hwy::TargetName(available & -available);  // the lowest bit is the best target
}

std::vector<const char*> supportedTargets() {
    const std::int64_t forced = forcedTarget;
    hwy::SetSupportedTargetsForTest(0);  // the machine's own list, whatever is forced now
    std::vector<const char*> names;
    for (std::int64_t target : hwy::SupportedAndGeneratedTargets()) names.push_back(hwy::TargetName(target));
    hwy::SetSupportedTargetsForTest(forced);
    return names;
}

bool forceTarget(const char* name) {
    std::int64_t chosen = 0;  // zero: no restriction
    hwy::SetSupportedTargetsForTest(0);
    if (name) {
        for (std::int64_t target : hwy::SupportedAndGeneratedTargets())
            if (std::string_view(hwy::TargetName(target)) == name) chosen = target;
        if (chosen == 0) {
            hwy::SetSupportedTargetsForTest(forcedTarget);
            return false;
        }
    }
    forcedTarget = chosen;
    hwy::SetSupportedTargetsForTest(chosen);
    hwy::GetChosenTarget().Update(hwy::SupportedTargets());
    return true;
}

}  // namespace hapticut::physics::kernels
#endif
