// The orbit camera: looks at a target from a distance, turned by yaw and pitch; rays through pixels.
#pragma once

#include <Eigen/Core>

#include <optional>

#include "hapticut/geometry/vec.h"

namespace hapticut::render {

struct OrbitCamera {
    Vec3 target = Vec3::Zero();
    double distance_m = 0.35;
    double yaw_rad = 0;      // about the world's y axis; 0 looks along -z (from +z)
    double pitch_rad = 0.2;  // up from the horizontal
    double fovY_rad = 0.7;
    /// Where the target shows across the image, in normalised device coordinates: 0 in the middle. The
    /// viewer moves it into the middle of what its panel leaves free, so the panel hides no organ.
    double centreX_ndc = 0;

    Vec3 eye() const;
    /// Unit vectors of the camera frame in world coordinates.
    Vec3 forward() const;
    Vec3 right() const;
    Vec3 up() const;
    Eigen::Matrix4d view() const;

    /// Turns by pixel drags, pans in the view plane, zooms by wheel clicks (10% each).
    void orbit(double dx_rad, double dy_rad);
    void pan(double dx_m, double dy_m);
    void zoom(double clicks);
    /// Frames a bounding sphere: target at its centre, close enough that the organ fills most of the height,
    /// or of the width where the part of the image it is framed in is narrower (`aspect` < 1, width / height).
    void frame(const Vec3& centre, double radius_m, double aspect = 1);
};

struct Ray {
    Vec3 origin, direction;  // direction unit length
};

/// The ray from the camera through a point given in normalised device coordinates (-1..1, y up),
/// for an image of the given aspect (width / height).
Ray rayThrough(const OrbitCamera& camera, double ndcX, double ndcY, double aspect);

/// Where a point shows in normalised device coordinates (-1..1, y up), the inverse of rayThrough;
/// nothing for a point at or behind the eye.
std::optional<Eigen::Vector2d> projectToNdc(const OrbitCamera& camera, const Vec3& point, double aspect);

/// The way a hand-held tool's handle points as this camera sees it: up and toward the viewer, as a hand
/// holds a pen. Tools of devices without an orientation are drawn so.
Vec3 toolHandleDirection(const OrbitCamera& camera);

/// Where the ray meets the plane through `point` facing the camera; the point itself if parallel.
Vec3 onPlaneFacingCamera(const OrbitCamera& camera, const Ray& ray, const Vec3& point);

}  // namespace hapticut::render
