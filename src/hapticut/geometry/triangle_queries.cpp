// Point-triangle and segment-triangle queries.
#include "hapticut/geometry/triangle_queries.h"

#include <cmath>

namespace hapticut::geometry {

ClosestOnTriangle closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Voronoi regions of the vertices, then the edges, then the interior.
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return {a, Vec3(1, 0, 0)};
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return {b, Vec3(0, 1, 0)};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return {a + v * ab, Vec3(1 - v, v, 0)};
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return {c, Vec3(0, 0, 1)};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return {a + w * ac, Vec3(1 - w, 0, w)};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {b + w * (c - b), Vec3(0, 1 - w, w)};
    }
    const double denom = 1 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    return {a + ab * v + ac * w, Vec3(1 - v - w, v, w)};
}

std::optional<SegmentHit> intersectSegmentTriangle(const Vec3& from, const Vec3& to, const Vec3& a, const Vec3& b,
                                                   const Vec3& c) {
    // Moller-Trumbore, two-sided, with a tolerance that closes the cracks along shared edges.
    constexpr double kEdgeTolerance = 1e-12;
    const Vec3 dir = to - from, e1 = b - a, e2 = c - a;
    const Vec3 pv = dir.cross(e2);
    const double det = e1.dot(pv);
    if (std::abs(det) < 1e-300) return std::nullopt;  // parallel to the plane
    const double inv = 1 / det;
    const Vec3 tv = from - a;
    const double u = tv.dot(pv) * inv;
    if (u < -kEdgeTolerance || u > 1 + kEdgeTolerance) return std::nullopt;
    const Vec3 qv = tv.cross(e1);
    const double v = dir.dot(qv) * inv;
    if (v < -kEdgeTolerance || u + v > 1 + kEdgeTolerance) return std::nullopt;
    const double t = e2.dot(qv) * inv;
    if (t < 0 || t > 1) return std::nullopt;
    return SegmentHit{t, Vec3(1 - u - v, u, v)};
}

}  // namespace hapticut::geometry
