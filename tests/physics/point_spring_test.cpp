// The tool's spring on the tissue (R9): the reaction spread with the thesis's squared weights sums to
// exactly minus the force on the tool; the force is clamped, damped by the device's velocity, and a
// tool pushes, never pulls.
#include <gtest/gtest.h>

#include <vector>

#include "hapticut/physics/point_spring.h"

namespace hapticut::physics {
namespace {

TEST(PointSpring, ContactWeightsAreTheNormalisedSquaredBarycentrics) {
    const Vec3 w = PointSpring::contactWeights(Vec3(0.2, 0.3, 0.5));
    EXPECT_NEAR(w.sum(), 1, 1e-15);
    EXPECT_NEAR(w.x() / w.y(), (0.2 * 0.2) / (0.3 * 0.3), 1e-12);
    const Vec3 edge = PointSpring::contactWeights(Vec3(2.0 / 3, 1.0 / 3, 0));
    EXPECT_NEAR(edge.x() / edge.y(), 4.0, 1e-12) << "twice as close, four times the share";
    EXPECT_EQ(edge.z(), 0);
    EXPECT_EQ(PointSpring::contactWeights(Vec3(1, 0, 0)), Vec3(1, 0, 0));
    EXPECT_EQ(PointSpring::contactWeights(Vec3(-0.1, 0, 0)), Vec3::Constant(1.0 / 3)) << "no share left: equal thirds";
}

/// A tool on the triangle (0,0,0), (1,0,0), (0,1,0) facing +z, pressed down from `anchor`.
PointSpring toolOnTriangle(const Vec3& bary, const Vec3& anchor_m) {
    PointSpring tool;
    tool.active = true;
    tool.touchTriangle({0, 1, 2}, bary);
    tool.anchor_m = anchor_m;
    tool.stiffness_N_per_m = 400;
    tool.normal = Vec3(0, 0, 1);
    return tool;
}

const std::vector<Vec3> kTriangle{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};

TEST(PointSpring, TheTissueGetsExactlyMinusTheForceOnTheToolSpreadBySquaredWeights) {
    const Vec3 bary(0.2, 0.3, 0.5);
    const PointSpring tool = toolOnTriangle(bary, Vec3(0.3, 0.2, -0.005));
    const Vec3 onTool = tool.forceOnTool(kTriangle);
    EXPECT_NEAR(onTool.z(), 400 * 0.005, 1e-12) << "Hooke's law from the contact point to the anchor";
    std::vector<Vec3> f(3, Vec3::Zero());
    tool.addReaction(kTriangle, f);
    EXPECT_LT((f[0] + f[1] + f[2] + onTool).norm(), 1e-15);
    EXPECT_NEAR(f[0].norm() / f[1].norm(), (0.2 * 0.2) / (0.3 * 0.3), 1e-12);
    PointSpring inactive = tool;
    inactive.active = false;
    std::vector<Vec3> none(3, Vec3::Zero());
    inactive.addReaction(kTriangle, none);
    EXPECT_EQ(none[0] + none[1] + none[2], Vec3::Zero());
}

TEST(PointSpring, ForceIsClampedDampedAndNeverPulls) {
    PointSpring tool = toolOnTriangle(Vec3(1, 0, 0), Vec3(0, 0, -0.1));  // 40 N unclamped
    tool.maxForce_N = 3.3;
    EXPECT_NEAR(tool.forceOnTool(kTriangle).norm(), 3.3, 1e-12);
    EXPECT_NEAR(tool.forceOnTool(kTriangle).normalized().z(), 1, 1e-12);
    tool.scale = 0.5;  // the ramp applies after the clamp
    EXPECT_NEAR(tool.forceOnTool(kTriangle).norm(), 1.65, 1e-12);
    PointSpring damped = toolOnTriangle(Vec3(1, 0, 0), Vec3(0, 0, -0.001));
    damped.bias_N = Vec3(0, 0, -0.2);  // b v with the device moving down at 0.1 m/s, b = 2 N s/m
    EXPECT_NEAR(damped.forceOnTool(kTriangle).z(), 0.4 + 0.2, 1e-12);
    const PointSpring pulling = toolOnTriangle(Vec3(1, 0, 0), Vec3(0, 0, 0.002));  // the device above the surface
    EXPECT_EQ(pulling.forceOnTool(kTriangle), Vec3::Zero());
}

TEST(PointSpring, ASpreadLoadIsTheGradientOfTheSpringsEnergy) {
    // Spread over nodes with weights w, the spring holds p = Σ w_i x_i, so each node's reaction
    // -w_i F must equal minus the gradient of E = k |p - anchor|² / 2 in that node's position.
    const std::vector<Vec3> x{Vec3(0, 0, 0), Vec3(0.004, 0, 0.0002), Vec3(0, 0.003, -0.0001), Vec3(0.003, 0.003, 0)};
    PointSpring tool;
    tool.active = true;
    tool.spread = true;
    tool.count = 4;
    const double w[] = {0.4, 0.3, 0.2, 0.1};
    for (std::uint32_t i = 0; i < 4; ++i) tool.nodes[i] = i, tool.weights[i] = w[i];
    tool.anchor_m = Vec3(0.001, 0.001, -0.004);
    tool.stiffness_N_per_m = 400;
    tool.normal = Vec3(0, 0, 1);
    std::vector<Vec3> f(4, Vec3::Zero());
    tool.addReaction(x, f);
    auto energy = [&](const std::vector<Vec3>& y) {
        return 0.5 * tool.stiffness_N_per_m * (tool.heldPoint(y) - tool.anchor_m).squaredNorm();
    };
    const double h = 1e-7;
    for (std::size_t i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) {
            std::vector<Vec3> plus = x, minus = x;
            plus[i][c] += h, minus[i][c] -= h;
            EXPECT_NEAR(f[i][c], -(energy(plus) - energy(minus)) / (2 * h), 1e-6) << "node " << i << " axis " << c;
        }
    Vec3 sum = Vec3::Zero();
    for (const Vec3& fi : f) sum += fi;
    EXPECT_LT((sum + tool.forceOnTool(x)).norm(), 1e-14) << "the tissue gets exactly minus the force on the tool";
    PointSpring copy;
    tool.copyTo(copy);
    EXPECT_EQ(copy.forceOnTool(x), tool.forceOnTool(x)) << "what is in use is copied";
}

}  // namespace
}  // namespace hapticut::physics
