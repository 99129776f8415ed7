// Point-triangle and segment-triangle queries with barycentric coordinates.
#pragma once

#include <optional>

#include "hapticut/geometry/vec.h"

namespace hapticut::geometry {

struct ClosestOnTriangle {
    Vec3 point;
    Vec3 bary;  // weights of a, b, c; point = bary.x a + bary.y b + bary.z c
};

/// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
ClosestOnTriangle closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

struct SegmentHit {
    double t;   // fraction along the segment, 0 at `from`
    Vec3 bary;  // barycentric coordinates of the hit on the triangle
};

/// Where the segment from -> to crosses triangle abc, from either side (back faces count, R10).
/// Edges and corners count as inside, so a segment through a shared edge hits one of its faces.
std::optional<SegmentHit> intersectSegmentTriangle(const Vec3& from, const Vec3& to, const Vec3& a, const Vec3& b,
                                                   const Vec3& c);

}  // namespace hapticut::geometry
