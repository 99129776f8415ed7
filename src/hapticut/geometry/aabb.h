// Axis-aligned bounding box.
#pragma once

#include <limits>
#include <span>

#include "hapticut/geometry/vec.h"

namespace hapticut::geometry {

struct Aabb {
    Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());

    bool empty() const { return (min.array() > max.array()).any(); }
    void grow(const Vec3& p) {
        min = min.cwiseMin(p);
        max = max.cwiseMax(p);
    }
    Vec3 center() const { return 0.5 * (min + max); }
    Vec3 extent() const { return max - min; }
};

inline Aabb boundsOf(std::span<const Vec3> points) {
    Aabb box;
    for (const Vec3& p : points) box.grow(p);
    return box;
}

}  // namespace hapticut::geometry
