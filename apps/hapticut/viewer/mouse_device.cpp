// Cursor rays to device positions.
#include "viewer/mouse_device.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hapticut/geometry/triangle_queries.h"

namespace hapticut::viewer {

std::optional<Vec3> pickSurface(const render::Ray& ray, std::span<const Vec3> positions,
                                std::span<const mesh::Face> faces) {
    // Brute force: runs once per frame when the cursor moves, far from the haptic loop.
    const double reach_m = 100;
    const Vec3 to = ray.origin + ray.direction * reach_m;
    double nearest = std::numeric_limits<double>::infinity();
    for (const mesh::Face& f : faces) {
        if (f[0] >= positions.size() || f[1] >= positions.size() || f[2] >= positions.size()) continue;
        if (const auto hit =
                geometry::intersectSegmentTriangle(ray.origin, to, positions[f[0]], positions[f[1]], positions[f[2]]))
            nearest = std::min(nearest, hit->t);
    }
    if (!std::isfinite(nearest)) return std::nullopt;
    return ray.origin + ray.direction * (nearest * reach_m);
}

Vec3 MouseDriver::hover(const render::OrbitCamera& camera, const render::Ray& ray,
                        const std::optional<Vec3>& hit) const {
    if (hit) return *hit - camera.forward() * kHoverStandoff_m;
    return render::onPlaneFacingCamera(camera, ray, camera.target);
}

void MouseDriver::engage(const render::OrbitCamera& camera, const render::Ray& ray, const std::optional<Vec3>& hit) {
    engaged_ = true;
    push_m_ = 0;
    anchor_m_ = hit ? *hit : render::onPlaneFacingCamera(camera, ray, camera.target);
}

void MouseDriver::push(double clicks) {
    push_m_ = std::clamp(push_m_ + clicks * kPushPerClick_m, -kMaxPush_m, kMaxPush_m);
}

Vec3 MouseDriver::drag(const render::OrbitCamera& camera, const render::Ray& ray,
                       const std::optional<Vec3>& pushAxis) const {
    return render::onPlaneFacingCamera(camera, ray, anchor_m_) + pushAxis.value_or(camera.forward()) * push_m_;
}

}  // namespace hapticut::viewer
