// Stereo projection (SPEC R20): the parallel-axis asymmetric frustum, one per eye, and the modes.
#pragma once

#include <optional>
#include <string_view>

#include <Eigen/Core>

namespace hapticut::render {

enum class StereoMode { Off, QuadBuffer, Anaglyph, SideBySide };
enum class Eye { Centre, Left, Right };

std::optional<StereoMode> parseStereoMode(std::string_view name);
std::string_view stereoModeName(StereoMode mode);

/// What the eyes see through: a symmetric lens (vertical field of view, aspect) and, for stereo, the
/// distance between the eyes and the focal length (the distance at which both eyes' images coincide).
struct Lens {
    double fovY_rad = 0.7;
    double aspect = 4.0 / 3.0;  // width / height of one eye's image
    double near_m = 0.01, far_m = 2.0;
    double eyeSeparation_m = 0.012;  // scaled to the scene: the heart is 12 cm across
    double focalLength_m = 0.35;     // put at the organ's centre, so it sits at the screen
    double centreX_ndc = 0;          // where the view's axis shows across the image (OrbitCamera's)
};

/// glFrustum's six planes plus where the eye sits along the camera's x axis.
struct Frustum {
    double left = 0, right = 0, bottom = 0, top = 0, near = 0, far = 0;
    double eyeOffset_m = 0;  // the eye's x in camera coordinates: -e/2, 0, +e/2
};

/// Parallel axes, not toe-in: both eyes look straight ahead, each frustum shifted toward the other
/// eye so the two coincide on the focal plane, which gives no vertical parallax.
Frustum eyeFrustum(const Lens& lens, Eye eye);

/// The projection matrix of a frustum (as glFrustum builds it).
Eigen::Matrix4d projectionMatrix(const Frustum& f);

/// The view matrix of one eye: the camera's view moved by the eye's offset along the camera's x.
Eigen::Matrix4d eyeView(const Eigen::Matrix4d& cameraView, const Frustum& f);

}  // namespace hapticut::render
