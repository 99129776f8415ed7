// The mouse as a haptic device: picking the surface, hovering above it, pressing in with the wheel.
#include <gtest/gtest.h>

#include <cmath>

#include "hapticut/mesh/procedural/primitives.h"
#include "viewer/mouse_device.h"

namespace hapticut::viewer {
namespace {

TEST(MouseDevice, PicksTheNearestSurfaceAndMissesBesideIt) {
    const mesh::SurfaceMesh sphere = mesh::procedural::makeSphere(Vec3::Zero(), 0.05, 32, 16);
    render::OrbitCamera camera;
    camera.pitch_rad = 0;
    camera.distance_m = 0.3;
    const auto hit = pickSurface(render::rayThrough(camera, 0, 0, 1), sphere.positions, sphere.faces);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->z(), 0.05, 1e-3);  // the front, not the back
    EXPECT_FALSE(pickSurface(render::rayThrough(camera, 0.9, 0.9, 1), sphere.positions, sphere.faces));
}

TEST(MouseDevice, HoversAboveTheSurfaceAndPressesInOneMillimetreAClick) {
    const mesh::SurfaceMesh sphere = mesh::procedural::makeSphere(Vec3::Zero(), 0.05, 32, 16);
    render::OrbitCamera camera;
    camera.pitch_rad = 0;
    camera.distance_m = 0.3;
    const render::Ray ray = render::rayThrough(camera, 0, 0, 1);
    const auto hit = pickSurface(ray, sphere.positions, sphere.faces);
    MouseDriver mouse;
    EXPECT_NEAR(mouse.hover(camera, ray, hit).z() - hit->z(), MouseDriver::kHoverStandoff_m, 1e-12);
    mouse.engage(camera, ray, hit);
    EXPECT_TRUE(mouse.drag(camera, ray).isApprox(*hit, 1e-12));
    mouse.push(3);
    EXPECT_NEAR(hit->z() - mouse.drag(camera, ray).z(), 0.003, 1e-12);
    // Moving the cursor moves the device in the plane through the point first touched.
    const Vec3 moved = mouse.drag(camera, render::rayThrough(camera, 0.1, 0, 1));
    EXPECT_NEAR(moved.z(), hit->z() - 0.003, 1e-12);
    // The plane lies 0.3 - 0.05 m from the eye; a tenth of the half-width there is 0.25 tan(fov/2) / 10.
    EXPECT_NEAR(moved.x(), 0.25 * std::tan(camera.fovY_rad / 2) * 0.1, 1e-6);
    // A blade held along its handle is pushed along it: its line still goes in where the cursor engaged.
    const Vec3 handle = render::toolHandleDirection(camera);
    const Vec3 held = mouse.drag(camera, ray, -handle);
    EXPECT_NEAR((held - *hit).norm(), 0.003, 1e-12);
    EXPECT_NEAR((held - *hit).normalized().dot(-handle), 1, 1e-12);
    mouse.push(1e6);
    EXPECT_NEAR(mouse.push_m(), MouseDriver::kMaxPush_m, 1e-12);
    mouse.release();
    EXPECT_FALSE(mouse.engaged());
}

}  // namespace
}  // namespace hapticut::viewer
