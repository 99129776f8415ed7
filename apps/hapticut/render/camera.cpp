// The orbit camera and picking rays.
#include "render/camera.h"

#include <algorithm>
#include <cmath>

namespace hapticut::render {

Vec3 OrbitCamera::forward() const {
    return Vec3(-std::sin(yaw_rad) * std::cos(pitch_rad), -std::sin(pitch_rad),
                -std::cos(yaw_rad) * std::cos(pitch_rad));
}

Vec3 OrbitCamera::right() const { return forward().cross(Vec3::UnitY()).normalized(); }

Vec3 OrbitCamera::up() const { return right().cross(forward()); }

Vec3 toolHandleDirection(const OrbitCamera& camera) {
    return (0.8 * camera.up() - 0.6 * camera.forward()).normalized();
}

Vec3 OrbitCamera::eye() const { return target - distance_m * forward(); }

Eigen::Matrix4d OrbitCamera::view() const {
    const Vec3 f = forward(), r = right(), u = up(), e = eye();
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<1, 3>(0, 0) = r.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -r.dot(e);
    m(1, 3) = -u.dot(e);
    m(2, 3) = f.dot(e);
    return m;
}

void OrbitCamera::orbit(double dx_rad, double dy_rad) {
    yaw_rad += dx_rad;
    // Short of the poles, where "up" would flip.
    pitch_rad = std::clamp(pitch_rad + dy_rad, -1.5, 1.5);
}

void OrbitCamera::pan(double dx_m, double dy_m) { target += dx_m * right() + dy_m * up(); }

void OrbitCamera::zoom(double clicks) { distance_m = std::clamp(distance_m * std::pow(0.9, clicks), 1e-3, 1e3); }

void OrbitCamera::frame(const Vec3& centre, double radius_m, double aspect) {
    target = centre;
    // Half the narrower side's angle of view; a box's bounding sphere is generous, hence 0.95.
    const double halfAngle = std::atan(std::tan(fovY_rad / 2) * std::min(aspect, 1.0));
    distance_m = 0.95 * radius_m / std::sin(halfAngle);
}

Ray rayThrough(const OrbitCamera& camera, double ndcX, double ndcY, double aspect) {
    const double h = std::tan(camera.fovY_rad / 2);
    const Vec3 d =
        camera.forward() + (ndcX - camera.centreX_ndc) * h * aspect * camera.right() + ndcY * h * camera.up();
    return {camera.eye(), d.normalized()};
}

std::optional<Eigen::Vector2d> projectToNdc(const OrbitCamera& camera, const Vec3& point, double aspect) {
    const Vec3 d = point - camera.eye();
    const double depth = d.dot(camera.forward());
    if (depth <= 1e-12) return std::nullopt;
    const double h = std::tan(camera.fovY_rad / 2);
    return Eigen::Vector2d(camera.centreX_ndc + d.dot(camera.right()) / (depth * h * aspect),
                           d.dot(camera.up()) / (depth * h));
}

Vec3 onPlaneFacingCamera(const OrbitCamera& camera, const Ray& ray, const Vec3& point) {
    const Vec3 n = camera.forward();
    const double denom = ray.direction.dot(n);
    if (std::abs(denom) < 1e-12) return point;
    return ray.origin + ray.direction * ((point - ray.origin).dot(n) / denom);
}

}  // namespace hapticut::render
