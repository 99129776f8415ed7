// Ray-parity inside test.
#include "hapticut/collision/point_inside.h"

namespace hapticut::collision {

bool insideClosedSurface(const Bvh& bvh, const SurfaceView& surface, const Vec3& p) {
    static const Vec3 kDirections[3] = {Vec3(0.5773, 0.6181, 0.5335).normalized(),
                                        Vec3(-0.7071, 0.1201, 0.6967).normalized(),
                                        Vec3(0.2113, -0.9123, 0.3507).normalized()};
    constexpr double kFar_m = 100;  // well outside any organ model
    int inside = 0;
    for (const Vec3& d : kDirections) inside += bvh.countCrossings(surface, p, p + kFar_m * d) % 2;
    return inside >= 2;
}

double penetrationDepth(const Bvh& bvh, const SurfaceView& surface, const Vec3& p) {
    if (!insideClosedSurface(bvh, surface, p)) return 0;
    const auto closest = bvh.closestPoint(surface, p);
    return closest ? closest->distance : 0;
}

}  // namespace hapticut::collision
