// Small triangle queries: normal, area, angles.
#pragma once

#include "hapticut/geometry/vec.h"

namespace hapticut::geometry {

/// Unnormalised normal (b - a) x (c - a); its length is twice the area.
inline Vec3 areaNormal(const Vec3& a, const Vec3& b, const Vec3& c) { return (b - a).cross(c - a); }

inline double triangleArea(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * areaNormal(a, b, c).norm(); }

/// Unit normal, or zero for a degenerate triangle.
Vec3 unitNormal(const Vec3& a, const Vec3& b, const Vec3& c);

/// Smallest interior angle in radians (0 for a degenerate triangle).
double minAngle(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace hapticut::geometry
