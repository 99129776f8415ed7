// The stereo frustum (R20) against hand-computed values, and the orbit camera's frames and rays.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "render/camera.h"
#include "render/stereo.h"

namespace hapticut::render {
namespace {

Lens handLens() {
    Lens lens;
    lens.fovY_rad = 2 * std::atan(0.5);  // tan(fov/2) = 0.5
    lens.aspect = 2;
    lens.near_m = 0.1;
    lens.far_m = 10;
    lens.eyeSeparation_m = 0.06;
    lens.focalLength_m = 2;
    return lens;
}

TEST(Stereo, CentreEyeIsTheSymmetricFrustum) {
    const Frustum f = eyeFrustum(handLens(), Eye::Centre);
    // top = near tan(fov/2) = 0.05; half width = aspect * top = 0.1.
    EXPECT_NEAR(f.top, 0.05, 1e-12);
    EXPECT_NEAR(f.bottom, -0.05, 1e-12);
    EXPECT_NEAR(f.left, -0.1, 1e-12);
    EXPECT_NEAR(f.right, 0.1, 1e-12);
    EXPECT_EQ(f.eyeOffset_m, 0);
}

TEST(Stereo, EyeFrustaShiftTowardEachOtherByHalfTheSeparationScaledToTheNearPlane) {
    // shift = (e/2) near / focal = 0.03 * 0.1 / 2 = 0.0015.
    const Frustum left = eyeFrustum(handLens(), Eye::Left), right = eyeFrustum(handLens(), Eye::Right);
    EXPECT_NEAR(left.left, -0.1 + 0.0015, 1e-12);
    EXPECT_NEAR(left.right, 0.1 + 0.0015, 1e-12);
    EXPECT_NEAR(right.left, -0.1 - 0.0015, 1e-12);
    EXPECT_NEAR(right.right, 0.1 - 0.0015, 1e-12);
    EXPECT_NEAR(left.eyeOffset_m, -0.03, 1e-12);
    EXPECT_NEAR(right.eyeOffset_m, 0.03, 1e-12);
    // Parallel axes: no vertical shift, so no vertical parallax.
    EXPECT_EQ(left.top, right.top);
    EXPECT_EQ(left.bottom, right.bottom);
}

TEST(Stereo, BothEyesSeeAPointOnTheFocalPlaneAtTheSamePlaceAndANearerOneApart) {
    const Lens lens = handLens();
    const auto ndcX = [&](Eye eye, const Eigen::Vector4d& world) {
        const Frustum f = eyeFrustum(lens, eye);
        const Eigen::Vector4d clip = projectionMatrix(f) * eyeView(Eigen::Matrix4d::Identity(), f) * world;
        return clip.x() / clip.w();
    };
    const Eigen::Vector4d onFocalPlane(0.3, 0.1, -lens.focalLength_m, 1), nearer(0.3, 0.1, -1.0, 1),
        further(0.3, 0.1, -4.0, 1);
    EXPECT_NEAR(ndcX(Eye::Left, onFocalPlane), ndcX(Eye::Right, onFocalPlane), 1e-12);
    // Nearer than the focal plane: crossed disparity (the left eye sees it further right).
    EXPECT_GT(ndcX(Eye::Left, nearer) - ndcX(Eye::Right, nearer), 0.01);
    EXPECT_LT(ndcX(Eye::Left, further) - ndcX(Eye::Right, further), -0.005);
}

// The viewer shows the view's axis in the middle of what its panel leaves free: a point on the axis
// lands there in each eye's image, and the frustum keeps its width.
TEST(Stereo, AnAxisShownOffTheMiddleLandsThereInEveryEye) {
    Lens lens = handLens();
    lens.centreX_ndc = 0.3;
    const Eigen::Vector4d onAxisAtFocus(0, 0, -lens.focalLength_m, 1);
    for (const Eye eye : {Eye::Centre, Eye::Left, Eye::Right}) {
        const Frustum f = eyeFrustum(lens, eye);
        const Eigen::Vector4d clip = projectionMatrix(f) * eyeView(Eigen::Matrix4d::Identity(), f) * onAxisAtFocus;
        EXPECT_NEAR(clip.x() / clip.w(), 0.3, 1e-12);
        EXPECT_NEAR(f.right - f.left, 0.2, 1e-12);
    }
}

TEST(Stereo, ProjectionMatchesGlFrustum) {
    Frustum f{-1, 3, -2, 2, 1, 5, 0};
    const Eigen::Matrix4d p = projectionMatrix(f);
    EXPECT_NEAR(p(0, 0), 2.0 / 4, 1e-12);
    EXPECT_NEAR(p(0, 2), 2.0 / 4, 1e-12);
    EXPECT_NEAR(p(1, 1), 2.0 / 4, 1e-12);
    EXPECT_NEAR(p(1, 2), 0, 1e-12);
    EXPECT_NEAR(p(2, 2), -6.0 / 4, 1e-12);
    EXPECT_NEAR(p(2, 3), -10.0 / 4, 1e-12);
    EXPECT_EQ(p(3, 2), -1);
    EXPECT_EQ(p(3, 3), 0);
}

TEST(Stereo, ModesParseAndPrintBack) {
    for (const char* name : {"off", "quad", "anaglyph", "side-by-side"})
        EXPECT_EQ(stereoModeName(*parseStereoMode(name)), name);
    EXPECT_FALSE(parseStereoMode("toe-in"));
}

TEST(Camera, ViewPutsTheEyeAtTheOriginLookingDownMinusZ) {
    OrbitCamera c;
    c.target = Vec3(0.1, -0.2, 0.3);
    c.distance_m = 0.5;
    c.yaw_rad = 0.7;
    c.pitch_rad = -0.3;
    const Eigen::Matrix4d v = c.view();
    EXPECT_TRUE((v * c.eye().homogeneous()).head<3>().isZero(1e-12));
    EXPECT_TRUE((v * c.target.homogeneous()).head<3>().isApprox(Vec3(0, 0, -0.5), 1e-12));
    EXPECT_NEAR(c.right().dot(c.up()), 0, 1e-12);
    EXPECT_NEAR(c.up().y(), std::cos(c.pitch_rad), 1e-12);  // up stays up
}

TEST(Camera, TheCentreRayIsTheViewDirectionAndHitsThePlaneThroughTheTarget) {
    OrbitCamera c;
    c.target = Vec3(0, 0, 0.02);
    const Ray centre = rayThrough(c, 0, 0, 1.5);
    EXPECT_TRUE(centre.direction.isApprox(c.forward(), 1e-12));
    EXPECT_TRUE(onPlaneFacingCamera(c, centre, c.target).isApprox(c.target, 1e-12));
    // The top edge of the image is half the field of view up.
    const Ray top = rayThrough(c, 0, 1, 1.5);
    EXPECT_NEAR(std::acos(top.direction.dot(c.forward())), c.fovY_rad / 2, 1e-12);
}

// A point on any pixel's ray projects back to that pixel, at any distance along it; a point behind the
// eye has no pixel.
TEST(Camera, APointProjectsBackToThePixelWhoseRayItLiesOn) {
    OrbitCamera c;
    c.target = Vec3(0.01, -0.02, 0.03);
    c.yaw_rad = 0.7;
    c.pitch_rad = -0.3;
    for (const double centre : {0.0, 0.3})  // the target in the middle, and beside a panel
        for (const auto& [x, y] : {std::pair{0.0, 0.0}, std::pair{-0.8, 0.5}, std::pair{0.99, -0.99}})
            for (const double along : {0.05, 0.4, 3.0}) {
                c.centreX_ndc = centre;
                const Ray ray = rayThrough(c, x, y, 1.6);
                const auto ndc = projectToNdc(c, ray.origin + along * ray.direction, 1.6);
                ASSERT_TRUE(ndc);
                EXPECT_NEAR(ndc->x(), x, 1e-9);
                EXPECT_NEAR(ndc->y(), y, 1e-9);
            }
    EXPECT_FALSE(projectToNdc(c, c.eye() - 0.1 * c.forward(), 1.6));
}

TEST(Camera, ATargetShownOffTheMiddleIsWhereTheRayThroughThatPointLooks) {
    OrbitCamera c;
    c.target = Vec3(0.01, -0.02, 0.03);
    c.centreX_ndc = 0.3;
    const auto target = projectToNdc(c, c.target, 1.6);
    ASSERT_TRUE(target);
    EXPECT_NEAR(target->x(), 0.3, 1e-12);
    EXPECT_NEAR(target->y(), 0, 1e-12);
    EXPECT_TRUE(rayThrough(c, 0.3, 0, 1.6).direction.isApprox(c.forward(), 1e-12));
}

TEST(Camera, FramingFitsTheSphereInTheViewAndZoomIsMultiplicative) {
    OrbitCamera c;
    c.frame(Vec3(1, 2, 3), 0.1);
    EXPECT_EQ(c.target, Vec3(1, 2, 3));
    EXPECT_GT(c.distance_m * std::sin(c.fovY_rad / 2), 0.09);
    const double d = c.distance_m;
    c.zoom(2);
    EXPECT_NEAR(c.distance_m, d * 0.81, 1e-12);
    c.orbit(0, 10);
    EXPECT_LE(c.pitch_rad, 1.5);
}

// Framed in a part of the image narrower than tall (the viewer's window beside its panel), the sphere
// fits the width: it stands farther back, by the width's angle of view instead of the height's.
TEST(Camera, FramingInANarrowPartOfTheImageFitsTheSphereInItsWidth) {
    OrbitCamera tall, narrow;
    tall.frame(Vec3::Zero(), 0.1);
    narrow.frame(Vec3::Zero(), 0.1, 0.6);
    const double halfWidthAngle = std::atan(std::tan(narrow.fovY_rad / 2) * 0.6);
    EXPECT_GT(narrow.distance_m * std::sin(halfWidthAngle), 0.09);
    EXPECT_LT(narrow.distance_m * std::sin(halfWidthAngle), 0.1);
    EXPECT_GT(narrow.distance_m, tall.distance_m * 1.5);
    OrbitCamera wide;
    wide.frame(Vec3::Zero(), 0.1, 1.8);  // wider than tall: the height decides, as before
    EXPECT_DOUBLE_EQ(wide.distance_m, tall.distance_m);
}

}  // namespace
}  // namespace hapticut::render
