// What the window says over the scene wherever the panel is: how to start, the last message, the force at
// each tool.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>

#include "hapticut/geometry/vec.h"
#include "render/camera.h"
#include "render/stereo.h"

namespace hapticut::viewer {

/// The last thing the viewer told the user. News fades after kNewsSeconds; an error stays until the next
/// message, so a failed load is read in the window, not in a terminal the user may not have.
struct Notice {
    static constexpr double kNewsSeconds = 10;
    std::string text;
    bool error = false;
    double since_s = 0;  // ImGui's clock when it was given

    void say(std::string what, bool isError);
    bool visibleAt(double now_s) const { return !text.empty() && (error || now_s - since_s < kNewsSeconds); }
};

/// The notice at the bottom of the window, centred in the part right of `left_px` (the panel's edge),
/// red for an error.
void drawNotice(const Notice& notice, double now_s, float left_px);

/// How to start, above the notice, until the mouse first takes hold of the organ.
void drawStartHint(bool twoHands, float left_px);

/// Where a point shows in the window, in pixels from its top left, for each view the stereo mode draws
/// (two for side by side): nothing for a view the point is behind.
struct ScreenPoints {
    std::array<std::optional<Vec2>, 2> at;
};
ScreenPoints toWindow(const render::OrbitCamera& camera, render::StereoMode mode, const Vec3& point, double width,
                      double height);

/// One hand as the overlay shows it.
struct HandMark {
    Vec3 proxy_m;
    double force_N = 0;
    bool contact = false;
};

/// Beside each tool in contact: |F| in newtons and a ring that grows with it toward the device's maximum,
/// green to red like the arrow. The mouse presses along the view, so the arrow points at the eye and the
/// dent faces it; the ring and the number show the press from any angle.
void drawForceMarks(std::span<const HandMark> hands, double maxForce_N, const render::OrbitCamera& camera,
                    render::StereoMode mode, double width, double height);

}  // namespace hapticut::viewer
