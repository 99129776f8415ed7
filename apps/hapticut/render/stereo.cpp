// Stereo projection: per-eye asymmetric frusta (Bourke's parallel-axis method).
#include "render/stereo.h"

#include <cmath>

namespace hapticut::render {

std::optional<StereoMode> parseStereoMode(std::string_view name) {
    if (name == "off" || name == "mono") return StereoMode::Off;
    if (name == "quad") return StereoMode::QuadBuffer;
    if (name == "anaglyph") return StereoMode::Anaglyph;
    if (name == "side-by-side") return StereoMode::SideBySide;
    return std::nullopt;
}

std::string_view stereoModeName(StereoMode mode) {
    switch (mode) {
        case StereoMode::Off: return "off";
        case StereoMode::QuadBuffer: return "quad";
        case StereoMode::Anaglyph: return "anaglyph";
        case StereoMode::SideBySide: return "side-by-side";
    }
    return "off";
}

Frustum eyeFrustum(const Lens& lens, Eye eye) {
    Frustum f;
    f.near = lens.near_m;
    f.far = lens.far_m;
    f.top = lens.near_m * std::tan(lens.fovY_rad / 2);
    f.bottom = -f.top;
    const double halfWidth = lens.aspect * f.top;
    const double side = eye == Eye::Left ? -1.0 : eye == Eye::Right ? 1.0 : 0.0;
    f.eyeOffset_m = side * lens.eyeSeparation_m / 2;
    // The focal plane's window, seen from an eye moved by eyeOffset, lies eyeOffset the other way:
    // scaled back to the near plane that is a shift of eyeOffset * near / focal.
    const double shift = f.eyeOffset_m * lens.near_m / lens.focalLength_m;
    // An axis shown off the middle, at x = c in device coordinates: the window moves the other way.
    const double offCentre = lens.centreX_ndc * halfWidth;
    f.left = -halfWidth - shift - offCentre;
    f.right = halfWidth - shift - offCentre;
    return f;
}

Eigen::Matrix4d projectionMatrix(const Frustum& f) {
    Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
    p(0, 0) = 2 * f.near / (f.right - f.left);
    p(0, 2) = (f.right + f.left) / (f.right - f.left);
    p(1, 1) = 2 * f.near / (f.top - f.bottom);
    p(1, 2) = (f.top + f.bottom) / (f.top - f.bottom);
    p(2, 2) = -(f.far + f.near) / (f.far - f.near);
    p(2, 3) = -2 * f.far * f.near / (f.far - f.near);
    p(3, 2) = -1;
    return p;
}

Eigen::Matrix4d eyeView(const Eigen::Matrix4d& cameraView, const Frustum& f) {
    Eigen::Matrix4d shift = Eigen::Matrix4d::Identity();
    shift(0, 3) = -f.eyeOffset_m;
    return shift * cameraView;
}

}  // namespace hapticut::render
