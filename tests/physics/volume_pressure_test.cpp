// Volume: the enclosed volume of a closed surface, and the pressure that keeps it, against a sphere's
// volume, the energy it is the gradient of, and a heart pressed with and without it.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/physics/material.h"
#include "hapticut/physics/volume_pressure.h"

namespace hapticut::physics {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(VolumePressure, TheEnclosedVolumeOfASphereConvergesAtSecondOrder) {
    // An inscribed polyhedron misses volume of the order of h^2: halving h quarters the error.
    double previous = 0;
    for (int segments : {16, 32, 64}) {
        const mesh::SurfaceMesh s = mesh::procedural::makeSphere(Vec3(0.3, -0.2, 0.1), 0.05, segments, segments / 2);
        const double error = std::abs(enclosedVolume(s.positions, s.faces) - 4.0 / 3 * kPi * std::pow(0.05, 3));
        if (previous > 0) {
            EXPECT_NEAR(previous / error, 4.0, 0.4) << segments << " segments";
        }
        previous = error;
    }
}

TEST(VolumePressure, TheForceIsMinusTheGradientOfTheVolumeEnergy) {
    mesh::SurfaceMesh s = mesh::procedural::makeSphere(Vec3::Zero(), 0.05, 12, 6);
    const double rest = enclosedVolume(s.positions, s.faces);
    for (Vec3& p : s.positions) p *= 0.97;  // squeezed: the pressure pushes out
    const double bulk = 2e5;
    auto energy = [&](const std::vector<Vec3>& x) {
        const double v = enclosedVolume(x, s.faces);
        return bulk * (v - rest) * (v - rest) / (2 * rest);
    };
    std::vector<Vec3> f(s.positions.size(), Vec3::Zero());
    addPressureForces(s.positions, s.faces, bulk, rest, f);
    for (std::size_t i : {std::size_t{0}, std::size_t{7}, s.positions.size() / 2}) {
        EXPECT_GT(f[i].dot(s.positions[i]), 0) << "outward, node " << i;
        for (int k = 0; k < 3; ++k) {
            std::vector<Vec3> plus = s.positions, minus = s.positions;
            const double h = 1e-7;
            plus[i][k] += h, minus[i][k] -= h;
            EXPECT_NEAR(f[i][k], -(energy(plus) - energy(minus)) / (2 * h), 1e-6 * f[i].norm() + 1e-12);
        }
    }
}

/// The heart pressed 6 mm at the front for a second; the volume it lost and how far its back moved out.
struct Pressed {
    double volumeLost_pct = 0, backOutward_m = 0;
};
Pressed pressTheHeart(double bulk_Pa) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    cutting::CutModel organ(heart, buildModel(heart, Material{}));
    Vec3 front(0, -0.01, -1);
    for (const Vec3& p : heart.positions)
        if (std::abs(p.x()) < 0.006 && std::abs(p.y() + 0.01) < 0.006 && p.z() > front.z()) front = p;
    haptics::Trajectory t;
    for (const auto& [time, z] : {std::pair{0.0, 0.03}, {0.5, 0.005}, {0.8, -0.006}, {1.8, -0.006}}) {
        haptics::TrajectoryPoint p;
        p.t_s = time;
        p.sample.position_m = front + Vec3(0, 0, z);
        t.points.push_back(p);
    }
    haptics::ReplayDevice device(t);
    haptics::LoopConfig config;
    config.bulkModulus_Pa = bulk_Pa;
    haptics::HapticLoop loop(organ, device, config);
    const double before = enclosedVolume(organ.model().nodes.position, heart.faces);
    haptics::runSimulated(loop, 1800, [](const haptics::StepOutput&) {});
    EXPECT_EQ(loop.stats().volumeKept, bulk_Pa > 0);
    EXPECT_GT(loop.stats().maxForce_N, 0.8) << "a press of about a newton";
    Pressed r;
    r.volumeLost_pct = 100 * (before - enclosedVolume(organ.model().nodes.position, heart.faces)) / before;
    // The back: nodes facing -z, away from the press; outward is away from the heart's centre.
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : heart.positions) centre += p;
    centre /= static_cast<double>(heart.positions.size());
    int back = 0;
    for (std::size_t i = 0; i < heart.positions.size(); ++i)
        if (heart.positions[i].z() < centre.z() - 0.01) {
            const Vec3 out = (heart.positions[i] - centre).normalized();
            r.backOutward_m += (organ.model().nodes.position[i] - heart.positions[i]).dot(out);
            ++back;
        }
    r.backOutward_m /= back;
    return r;
}

TEST(VolumePressure, ThePressedHeartKeepsItsVolumeAndBulgesAwayFromThePress) {
    const Pressed free = pressTheHeart(0), kept = pressTheHeart(3e5);
    EXPECT_GT(free.volumeLost_pct, 0.01) << "a press dents the heart";
    EXPECT_LT(kept.volumeLost_pct, 0.5 * free.volumeLost_pct) << "the pressure keeps most of the volume";
    EXPECT_GT(kept.backOutward_m, 1e-7) << "the back bulges outward";
    EXPECT_GT(kept.backOutward_m, 10 * std::abs(free.backOutward_m)) << "which, without volume, it hardly does";
}

}  // namespace
}  // namespace hapticut::physics
