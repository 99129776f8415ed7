// The god-object proxy: Hooke's law on a plane, never inside the heart while sliding fast over its
// edges and vertices, held in concave corners, pushed out by a moving surface, free when it leaves.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "hapticut/collision/point_inside.h"
#include "hapticut/haptics/proxy.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/mesh/vertex_faces.h"

namespace hapticut::haptics {
namespace {

struct Scene {
    mesh::SurfaceMesh mesh;
    collision::Bvh bvh;
    collision::SurfaceView view() const { return {mesh.positions, mesh.faces}; }
    void rebuild() { bvh.build(view()); }
};

/// The coupling spring's force on the hand, F = k (proxy - device), with no damping or clamp.
Vec3 hookeForce(const Vec3& proxy_m, const Vec3& device_m, double stiffness_N_per_m) {
    return stiffness_N_per_m * (proxy_m - device_m);
}

Scene plane() {
    Scene s{mesh::procedural::makeGrid(10, 0.01), {}};  // 0.1 m square at z = 0, facing +z
    s.rebuild();
    return s;
}

TEST(Proxy, PressingAFlatPlaneGivesHookesForceAlongTheNormal) {
    Scene s = plane();
    GodObjectProxy proxy;
    proxy.reset(Vec3(0.012, -0.007, 0.01));
    const double k = 500;  // N/m
    for (double depth : {0.0005, 0.001, 0.002, 0.004}) {
        const Vec3 device(0.012, -0.007, -depth);
        EXPECT_EQ(proxy.update(device, s.view(), s.bvh), 1);
        const Vec3 f = hookeForce(proxy.position(), device, k);
        EXPECT_NEAR(f.z(), k * (depth + proxy.params().offset_m), 1e-9);
        EXPECT_NEAR(f.x(), 0, 1e-12);
        EXPECT_NEAR(f.y(), 0, 1e-12);
        EXPECT_TRUE(proxy.contact().active);
    }
    EXPECT_EQ(proxy.pushOuts(), 0) << "every slide ended on the plane, none inside it";
}

TEST(Proxy, SlidesAlongAPlaneUnderAnObliqueDevice) {
    Scene s = plane();
    GodObjectProxy proxy;
    proxy.reset(Vec3(0, 0, 0.01));
    proxy.update(Vec3(0, 0, -0.002), s.view(), s.bvh);
    for (int i = 1; i <= 20; ++i) {
        const Vec3 device(0.001 * i, 0.0005 * i, -0.002);
        proxy.update(device, s.view(), s.bvh);
        EXPECT_NEAR(proxy.position().x(), device.x(), 1e-12);
        EXPECT_NEAR(proxy.position().y(), device.y(), 1e-12);
        EXPECT_NEAR(proxy.position().z(), proxy.params().offset_m, 1e-12);
    }
}

TEST(Proxy, LeavingTheSurfaceGivesZeroForce) {
    Scene s = plane();
    GodObjectProxy proxy;
    proxy.reset(Vec3(0, 0, 0.01));
    proxy.update(Vec3(0, 0, -0.003), s.view(), s.bvh);
    EXPECT_TRUE(proxy.contact().active);
    const Vec3 device(0.002, 0, 0.004);
    EXPECT_EQ(proxy.update(device, s.view(), s.bvh), 0);
    EXPECT_EQ(proxy.position(), device);
    EXPECT_FALSE(proxy.contact().active);
    EXPECT_EQ(hookeForce(proxy.position(), device, 500), Vec3::Zero());
}

TEST(Proxy, ConcaveCornerHoldsTheProxyAtTheCorner) {
    // Floor z = 0 and walls x = 0 and y = 0, all facing into the open octant.
    Scene s;
    s.mesh.positions = {Vec3(0, 0, 0),   Vec3(0.1, 0, 0),   Vec3(0.1, 0.1, 0), Vec3(0, 0.1, 0),  // floor
                        Vec3(0, 0, 0.1), Vec3(0, 0.1, 0.1), Vec3(0.1, 0, 0.1)};
    s.mesh.faces = {{0, 1, 2}, {0, 2, 3}, {0, 3, 5}, {0, 5, 4}, {0, 4, 6}, {0, 6, 1}};
    mesh::completeMesh(s.mesh);
    s.rebuild();
    const double off = ProxyParams{}.offset_m;
    GodObjectProxy proxy;
    proxy.reset(Vec3(0.05, 0.05, 0.05));
    // Into the edge between the floor and the y = 0 wall: held on that edge, free along x.
    EXPECT_EQ(proxy.update(Vec3(0.05, -0.02, -0.02), s.view(), s.bvh), 2);
    EXPECT_NEAR(proxy.position().x(), 0.05, 1e-9);
    EXPECT_NEAR(proxy.position().y(), off, 1e-9);
    EXPECT_NEAR(proxy.position().z(), off, 1e-9);
    proxy.update(Vec3(0.07, -0.02, -0.02), s.view(), s.bvh);
    EXPECT_NEAR(proxy.position().x(), 0.07, 1e-9) << "slides along the edge";
    EXPECT_NEAR(proxy.position().y(), off, 1e-9);
    // Into the corner itself: held by all three planes.
    proxy.reset(Vec3(0.05, 0.05, 0.05));
    EXPECT_EQ(proxy.update(Vec3(-0.01, -0.02, -0.03), s.view(), s.bvh), 3);
    EXPECT_LT((proxy.position() - Vec3(off, off, off)).norm(), 1e-9);
    for (int i = 0; i < 50; ++i) proxy.update(Vec3(-0.01, -0.02, -0.03), s.view(), s.bvh);
    EXPECT_LT((proxy.position() - Vec3(off, off, off)).norm(), 1e-9) << "the corner holds over many steps";
}

TEST(Proxy, SurfaceMovingIntoAStationaryDevicePushesTheProxyOut) {
    Scene s = plane();
    for (Vec3& p : s.mesh.positions) p.z() -= 0.005;  // start 5 mm below the device
    s.bvh.build(s.view());
    const Vec3 device(0.003, 0.004, 0);
    GodObjectProxy proxy;
    proxy.reset(device);
    double previousForce = 0;
    for (int step = 0; step < 150; ++step) {
        for (Vec3& p : s.mesh.positions) p.z() += 1e-4;  // 0.1 m/s at 1 kHz
        s.bvh.refit(s.view());
        proxy.update(device, s.view(), s.bvh);
        const double surfaceZ = s.mesh.positions[0].z();
        EXPECT_GE(proxy.position().z(), surfaceZ) << "step " << step;
        const double force = hookeForce(proxy.position(), device, 500).z();
        if (surfaceZ > 1e-4) {
            EXPECT_GT(force, previousForce) << "step " << step;
            EXPECT_NEAR(force, 500 * (surfaceZ + proxy.params().offset_m), 1e-6);
        }
        previousForce = force;
    }
    // The plane reached the proxy within its reach for a contact, which carried it from then on: it
    // was never found inside.
    EXPECT_EQ(proxy.pushOuts(), 0);
}

// A surface that jumps over a free proxy in one step (a fast organ, a reset) leaves it inside: the
// push-out puts it back on the surface and says how often and how deep, for the run's report.
TEST(Proxy, APushOutIsCountedWithHowDeepTheProxyWas) {
    Scene s = plane();
    const Vec3 device(0.003, 0.004, 0.0);
    GodObjectProxy proxy;
    proxy.reset(device + Vec3(0, 0, 0.001));
    proxy.update(device + Vec3(0, 0, 0.001), s.view(), s.bvh);  // free, a millimetre above the plane
    EXPECT_FALSE(proxy.contact().active);
    for (Vec3& p : s.mesh.positions) p.z() += 0.0015;  // the plane now half a millimetre above it
    s.bvh.refit(s.view());
    proxy.update(device, s.view(), s.bvh);
    EXPECT_EQ(proxy.pushOuts(), 1);
    EXPECT_NEAR(proxy.deepestPushOut_m(), 0.0005, 1e-9);
    EXPECT_NEAR(proxy.position().z(), 0.0015 + proxy.params().offset_m, 1e-9);
    proxy.update(device, s.view(), s.bvh);  // resting on it: nothing more to push
    EXPECT_EQ(proxy.pushOuts(), 1);
}

/// Drags the device along a closed path through the heart at up to 0.5 m/s (0.5 mm per 1 ms step)
/// and checks with the independent ray-parity test that the proxy is never inside.
void expectNeverInside(const Scene& s, auto path, int steps) {
    GodObjectProxy proxy(ProxyParams{.closedSurface = true});
    proxy.reset(Vec3(0, 0, 0.3));  // start well outside; the first update brings it to the surface
    int contacts = 0;
    for (int i = 0; i <= steps; ++i) {
        const Vec3 device = path(static_cast<double>(i) / steps);
        proxy.update(device, s.view(), s.bvh);
        ASSERT_FALSE(collision::insideClosedSurface(s.bvh, s.view(), proxy.position())) << "step " << i;
        if (collision::insideClosedSurface(s.bvh, s.view(), device)) {  // pressed in: the proxy rests on the surface
            EXPECT_LT(s.bvh.closestPoint(s.view(), proxy.position())->distance, 2e-4) << "step " << i;
        }
        contacts += proxy.contact().active;
    }
    EXPECT_GT(contacts, steps / 10) << "the path must actually touch the heart";
}

TEST(Proxy, NeverInsideTheHeartWhileSlidingOverEdgesAndVertices) {
    Scene s{mesh::procedural::makeHeart({}), {}};
    s.rebuild();
    const double twoPi = 2 * std::numbers::pi;
    // Around the heart at mid height, 8 mm inside the surface (circumference ~0.25 m in 500 steps).
    expectNeverInside(
        s, [&](double u) { return Vec3(0.03 * std::cos(twoPi * u), 0.0, 0.022 * std::sin(twoPi * u)); }, 500);
    // Over the apex and the vessels at the top, in the front-back plane.
    expectNeverInside(
        s, [&](double u) { return Vec3(0.004, 0.05 * std::cos(twoPi * u), 0.02 * std::sin(twoPi * u)); }, 600);
    // A wobbly path that enters and leaves repeatedly.
    expectNeverInside(
        s,
        [&](double u) {
            const double a = twoPi * u;
            return Vec3(0.045 * std::cos(3 * a), 0.05 * std::sin(2 * a), 0.03 * std::cos(5 * a + 0.3));
        },
        1500);
}

// The lips of a wound pressed through each other, as two closed boxes: the right one's face x = 9.8 mm
// lies 0.2 mm inside the left one, whose own face x = 10 mm is just behind it. A proxy resting on that
// face from the left is in the left tissue; the device drawn 1.2 mm further left, the proxy left the
// face with nothing in its way, and the faces round its nearest point (that face's) said outside: it
// stayed free in the tissue (a scalpel lifted out of a cut on a jittered heart went 1.8 mm in so).
TEST(Proxy, PulledOffLipsPressedThroughEachOtherItIsHeldOnThemNotLeftInTheTissue) {
    const std::vector<Vec2> left = {Vec2(0, 0), Vec2(0.010, 0), Vec2(0.010, 0.010), Vec2(0, 0.010)};
    const std::vector<Vec2> right = {Vec2(0.0098, 0.001), Vec2(0.020, 0.001), Vec2(0.020, 0.009), Vec2(0.0098, 0.009)};
    Scene s{mesh::procedural::makePrism(left, 0, 0.010), {}};
    mesh::procedural::appendMesh(s.mesh, mesh::procedural::makePrism(right, 0.001, 0.009));
    s.rebuild();
    const mesh::VertexFaces topology = mesh::buildVertexFaces(s.mesh.faces, s.mesh.positions.size());
    GodObjectProxy proxy(ProxyParams{.closedSurface = true});
    proxy.setTopology(&topology);
    const Vec3 onTheLip(0.0098 - proxy.params().offset_m, 0.005, 0.005);
    proxy.reset(onTheLip);
    proxy.update(onTheLip, s.view(), s.bvh);
    ASSERT_TRUE(proxy.contact().active) << "resting on the right box's face";
    const Vec3 device(0.00865, 0.005, 0.005);  // 1.35 mm inside the left box
    ASSERT_TRUE(collision::insideClosedSurface(s.bvh, s.view(), device));
    for (int step = 0; step < 10; ++step) {
        proxy.update(device, s.view(), s.bvh);
        EXPECT_GE(proxy.position().x(), 0.0098) << "step " << step << ": held on the lip it was pulled off";
        EXPECT_FALSE(collision::insideClosedSurface(s.bvh, s.view(), proxy.position())) << "step " << step;
        EXPECT_GT(hookeForce(proxy.position(), device, 400).x(), 0.45) << "step " << step << ": the lip pushes back";
    }
}

}  // namespace
}  // namespace hapticut::haptics

namespace hapticut::haptics {
namespace {

TEST(Proxy, TouchedFaceFastPathFindsTheSameContactAsTheTree) {
    // R12: two proxies driven by the same device over the heart, across edges, vertices and the
    // vessels; one searches the touched face's neighbourhood first, the other always the whole tree.
    Scene s{mesh::procedural::makeHeart({}), {}};
    s.rebuild();
    const mesh::VertexFaces topology = mesh::buildVertexFaces(s.mesh.faces, s.mesh.positions.size());
    GodObjectProxy fast(ProxyParams{.closedSurface = true}), full(ProxyParams{.closedSurface = true});
    fast.setTopology(&topology);
    fast.reset(Vec3(0, 0, 0.3));
    full.reset(Vec3(0, 0, 0.3));
    for (int i = 0; i <= 2000; ++i) {
        const double a = 2 * std::numbers::pi * i / 2000;
        const Vec3 device(0.045 * std::cos(3 * a), 0.05 * std::sin(2 * a), 0.03 * std::cos(5 * a + 0.3));
        fast.update(device, s.view(), s.bvh);
        full.update(device, s.view(), s.bvh);
        ASSERT_LT((fast.position() - full.position()).norm(), 1e-12) << "step " << i;
        ASSERT_EQ(fast.contact().active, full.contact().active) << "step " << i;
        if (fast.contact().active) {
            const Vec3 pf = pointOnFace(s.view(), fast.contact().face, fast.contact().bary);
            const Vec3 pt = pointOnFace(s.view(), full.contact().face, full.contact().bary);
            ASSERT_LT((pf - pt).norm(), 1e-12)
                << "step " << i << ": the same contact point (faces may differ on a shared edge)";
        }
    }
    EXPECT_GT(fast.fastPathContacts(), 200) << "the fast path must actually be used";
    EXPECT_EQ(full.fastPathContacts(), 0);
}

}  // namespace
}  // namespace hapticut::haptics

namespace hapticut::haptics {
namespace {

TEST(Proxy, FrictionSticksInsideTheStaticConeAndSlidesAtTheDynamicRatio) {
    Scene s = plane();
    const double off = ProxyParams{}.offset_m;
    GodObjectProxy proxy(ProxyParams{.staticFriction = 0.5, .dynamicFriction = 0.3});
    proxy.reset(Vec3(0, 0, 0.01));
    proxy.update(Vec3(0, 0, -0.004), s.view(), s.bvh);  // pressed 4 mm (+ offset) into the plane
    const Vec3 stuck = proxy.position();
    // Drag sideways by 1.5 mm: tangential/normal = 1.5/4 < 0.5, so the proxy sticks.
    proxy.update(Vec3(0.0015, 0, -0.004), s.view(), s.bvh);
    EXPECT_LT((proxy.position() - stuck).norm(), 1e-12);
    // Drag to 3 mm: 3/4 > 0.5, so it slips and lags so that tangential = 0.3 x normal.
    const Vec3 device(0.003, 0, -0.004);
    proxy.update(device, s.view(), s.bvh);
    const Vec3 f = hookeForce(proxy.position(), device, 400);
    EXPECT_NEAR(std::hypot(f.x(), f.y()) / f.z(), 0.3, 1e-9);
    EXPECT_LT(f.x(), 0) << "friction opposes the motion";
    EXPECT_NEAR(proxy.position().z(), off, 1e-12);
    // Without friction it would follow the device exactly.
    GodObjectProxy frictionless;
    frictionless.reset(Vec3(0, 0, 0.01));
    frictionless.update(device, s.view(), s.bvh);
    EXPECT_NEAR(frictionless.position().x(), device.x(), 1e-12);
}

}  // namespace
}  // namespace hapticut::haptics
