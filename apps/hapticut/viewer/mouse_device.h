// The mouse as a haptic device: hovering puts the tool just above the surface under the cursor; a
// held button engages it, the cursor then moves it in the plane facing the camera through the point
// first touched, and the wheel pushes it in or pulls it out along the view.
#pragma once

#include <optional>
#include <span>

#include "hapticut/mesh/surface_mesh.h"
#include "render/camera.h"

namespace hapticut::viewer {

/// The nearest point where the ray meets the surface, if it does.
std::optional<Vec3> pickSurface(const render::Ray& ray, std::span<const Vec3> positions,
                                std::span<const mesh::Face> faces);

class MouseDriver {
public:
    static constexpr double kHoverStandoff_m = 0.004;  // a hovering tool floats this far above the surface
    static constexpr double kPushPerClick_m = 0.001;   // one wheel click pushes a millimetre
    static constexpr double kMaxPush_m = 0.04;

    /// Where the device goes when the cursor hovers (nothing engaged): above the surface hit under the
    /// cursor, else on the plane through the camera's target.
    Vec3 hover(const render::OrbitCamera& camera, const render::Ray& ray, const std::optional<Vec3>& hit) const;
    /// Engages at the surface point under the cursor (or the plane through the target when missed).
    void engage(const render::OrbitCamera& camera, const render::Ray& ray, const std::optional<Vec3>& hit);
    void release() { engaged_ = false; }
    /// Wheel clicks while engaged: positive pushes into the view.
    void push(double clicks);
    /// Where the engaged device is for the cursor's ray: pushed in along the view, or along `pushAxis`
    /// (unit, into the tissue) for a tool held along it. A blade whose orientation the mouse reports is
    /// pushed along its own handle, so its line still goes in under the cursor, where the cut follows it.
    Vec3 drag(const render::OrbitCamera& camera, const render::Ray& ray,
              const std::optional<Vec3>& pushAxis = std::nullopt) const;

    bool engaged() const { return engaged_; }
    double push_m() const { return push_m_; }

private:
    bool engaged_ = false;
    Vec3 anchor_m_ = Vec3::Zero();
    double push_m_ = 0;
};

}  // namespace hapticut::viewer
