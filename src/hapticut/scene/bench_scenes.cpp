// Benchmark scenes.
#include "hapticut/scene/bench_scenes.h"

#include <cmath>

#include "hapticut/common/assert.h"
#include "hapticut/geometry/aabb.h"

namespace hapticut::scene {

Scene benchHeart(int triangles) {
    SceneRequest request;
    request.overrides.model = "heart";
    request.overrides.triangles = triangles;
    auto scene = loadScene(request);
    HAPTICUT_ASSERT(scene.has_value());  // the procedural heart needs no file
    return std::move(scene.value());
}

Vec3 slidingDevice_m(long step) {
    const double angle = static_cast<double>(step) * 0.2e-3 / 0.01;
    return Vec3(0.01 * std::cos(angle), 0.01 * std::sin(angle) - 0.01, 0.025);
}

Vec3 frontVertex_m(const mesh::SurfaceMesh& heart, double x_m, double y_m) {
    Vec3 front = geometry::boundsOf(heart.positions).center();
    for (const Vec3& p : heart.positions)
        if (std::abs(p.x() - x_m) < 0.01 && std::abs(p.y() - y_m) < 0.01 && p.z() > front.z()) front = p;
    return front;
}

}  // namespace hapticut::scene
