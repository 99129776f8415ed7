// Small triangle queries: normal, area, angles.
#include "hapticut/geometry/triangle.h"

#include <algorithm>
#include <cmath>

namespace hapticut::geometry {

Vec3 unitNormal(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = areaNormal(a, b, c);
    const double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

double minAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
    // atan2(|u x v|, u.v) stays accurate for angles near 0 and pi, unlike acos.
    auto angle = [](const Vec3& u, const Vec3& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); };
    const Vec3 ab = b - a, bc = c - b, ca = a - c;
    if (ab.squaredNorm() == 0 || bc.squaredNorm() == 0 || ca.squaredNorm() == 0) return 0;
    return std::min({angle(ab, -ca), angle(bc, -ab), angle(ca, -bc)});
}

}  // namespace hapticut::geometry
