// Four bounding boxes side by side in single precision, tested together: the nodes of a 4-wide BVH
// (Dammertz, Hanika & Keller 2008, "Shallow bounding volume hierarchies for fast SIMD ray tracing of
// incoherent rays"; Wald, Benthin & Boulos 2008, "Getting rid of packets").
//
// The boxes are stored as structure of arrays, so each test below is a handful of 4-lane float
// operations, written with the compiler's vector types (GCC and Clang). Four float lanes are the
// baseline vector of every x86-64 (SSE2) and arm64 (NEON) machine, and wider instruction sets add
// nothing to a four-box test, so the portable build has them and no run-time dispatch is needed.
//
// Single precision is exact enough because every test is conservative: a query widens the boxes by
// `slack`, a bound on the rounding of the stored boxes and of the query's own float arithmetic
// (WideNode::slack). A box may be entered that double precision would have skipped, never the other
// way round, and the triangles themselves are always tested in double precision.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "hapticut/geometry/aabb.h"

namespace hapticut::collision {

using Float4 = float __attribute__((vector_size(16)));
using Int4 = std::int32_t __attribute__((vector_size(16)));

inline Float4 lanewiseMin(Float4 a, Float4 b) { return a < b ? a : b; }
inline Float4 lanewiseMax(Float4 a, Float4 b) { return a < b ? b : a; }
/// Bit i set where lane i of a comparison's result is true.
inline unsigned laneBits(Int4 m) { return static_cast<unsigned>((m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8)); }

struct alignas(64) WideNode {
    static constexpr std::uint32_t kLeafBit = 0x80000000u;  // child: a leaf of the binary tree, not a wide node
    std::array<Float4, 3> lo{}, hi{};                       // per axis, the four lanes' bounds
    std::array<std::uint32_t, 4> child{};
    std::uint32_t lanes = 0;  // bit i set: lane i holds a box

    void set(int lane, const geometry::Aabb& box) {
        for (int k = 0; k < 3; ++k) {
            lo[static_cast<std::size_t>(k)][lane] = static_cast<float>(box.min[k]);
            hi[static_cast<std::size_t>(k)][lane] = static_cast<float>(box.max[k]);
        }
    }

    /// How far to widen every box for a query touching coordinates up to `query_scale` in magnitude,
    /// when the stored boxes reach up to `box_scale`. Storing a box rounds it by half a float unit, and
    /// the query's subtractions, products and sums round by a few more; 2^-18 is 32 times their sum.
    static float slack(double query_scale, double box_scale) {
        return static_cast<float>(std::ldexp(query_scale + box_scale, -18) + 1e-12);
    }
};

/// A segment from + t·dir, t in [0, 1], in single precision for the slab test against four boxes.
struct WideSegment {
    // Per axis: the start shifted by the slack either way, so a box widened by it is a subtraction away.
    std::array<float, 3> lowShift{}, highShift{}, invDir{};
    WideSegment(const Vec3& a, const Vec3& b, double box_scale) {
        const Vec3 dir = b - a;
        const double slack = WideNode::slack(std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()), box_scale);
        for (int k = 0; k < 3; ++k) {
            const auto axis = static_cast<std::size_t>(k);
            lowShift[axis] = static_cast<float>(a[k] + slack);
            highShift[axis] = static_cast<float>(a[k] - slack);
            // A direction parallel to an axis (or nearly) gets a large finite inverse: a box's slab
            // then spans the whole segment or none of it, and no 0 · inf appears (the slack keeps a
            // segment lying in a box's face plane inside the widened slab).
            constexpr double kHuge = 1e30;
            const double inv = dir[k] != 0 ? 1 / dir[k] : kHuge;
            invDir[axis] = static_cast<float>(std::clamp(inv, -kHuge, kHuge));
        }
    }

    /// Lanes whose widened box the segment meets within [0, t_max], as bits; where it enters each in `t`.
    unsigned meets(const WideNode& n, float t_max, Float4& t) const {
        Float4 t0 = {0, 0, 0, 0}, t1 = {t_max, t_max, t_max, t_max};
        for (std::size_t k = 0; k < 3; ++k) {
            const Float4 a = (n.lo[k] - lowShift[k]) * invDir[k];
            const Float4 b = (n.hi[k] - highShift[k]) * invDir[k];
            t0 = lanewiseMax(t0, lanewiseMin(a, b));
            t1 = lanewiseMin(t1, lanewiseMax(a, b));
        }
        t = t0;
        return laneBits(t0 <= t1) & n.lanes;
    }
};

/// A point in single precision for the distance test against four boxes.
struct WidePoint {
    std::array<float, 3> p{};
    float slack = 0;
    WidePoint(const Vec3& point, double box_scale) {
        for (int k = 0; k < 3; ++k) p[static_cast<std::size_t>(k)] = static_cast<float>(point[k]);
        slack = WideNode::slack(point.cwiseAbs().maxCoeff(), box_scale);
    }

    /// The squared distance in float that a box within sqrt(d2) of the point (in exact arithmetic) can
    /// measure at most: the threshold to accept lanes against. Infinite stays infinite.
    float reach(double d2) const {
        if (!std::isfinite(d2)) return std::numeric_limits<float>::infinity();
        const double r = std::sqrt(d2) + slack;
        return static_cast<float>(r * r * (1 + 1e-5));
    }

    /// Lanes whose box lies within the squared distance `reach_d2` (from `reach`), as bits; the
    /// squared distances in `d2`.
    unsigned within(const WideNode& n, float reach_d2, Float4& d2) const {
        d2 = Float4{0, 0, 0, 0};
        for (std::size_t k = 0; k < 3; ++k) {
            const Float4 d = lanewiseMax(lanewiseMax(n.lo[k] - p[k], p[k] - n.hi[k]), Float4{0, 0, 0, 0});
            d2 += d * d;
        }
        return laneBits(d2 <= reach_d2) & n.lanes;
    }
};

}  // namespace hapticut::collision
