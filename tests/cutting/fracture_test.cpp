// The fracture rule (Mahvash & Hayward): the crack advances only when the blade's pull along the surface
// exceeds toughness x depth, and then exactly so far that the pull equals it.
#include <gtest/gtest.h>

#include "hapticut/cutting/fracture.h"

namespace hapticut::cutting {
namespace {

TEST(Fracture, TheCrackHoldsUntilThePullAlongTheSurfacePaysForTheNewCut) {
    const FractureParams params{.toughness_J_per_m2 = 200};
    const Vec3 normal(0, 0, 1);
    const double k = 400, depth = 0.005;  // J x depth = 1 N: a stretch of 2.5 mm along the surface
    const Vec3 proxy(0, 0, 0);
    EXPECT_FALSE(advancedCrackTip(Vec3(0.0024, 0, -depth), proxy, normal, depth, k, params));
    // Pressing deeper is across the surface: it pulls nothing along it.
    EXPECT_FALSE(advancedCrackTip(Vec3(0.001, 0, -0.05), proxy, normal, depth, k, params));
    const auto tip = advancedCrackTip(Vec3(0.004, 0.003, -depth), proxy, normal, depth, k, params);
    ASSERT_TRUE(tip);
    // The tip is 2.5 mm back from the blade along the surface, on the line from the crack to the blade,
    // at the blade's depth: the pull that remains is exactly J x depth.
    const Vec3 pull = Vec3(0.004, 0.003, -depth) - *tip;
    EXPECT_NEAR(pull.z(), 0, 1e-15);
    EXPECT_NEAR(k * pull.norm(), 200 * depth, 1e-12);
    EXPECT_NEAR(pull.normalized().dot(Vec3(0.8, 0.6, 0)), 1, 1e-12);
}

TEST(Fracture, TheForceGrowsWithTheDepthWithinTheBladesEdge) {
    const FractureParams params{.toughness_J_per_m2 = 300, .minDepth_m = 0.001, .maxDepth_m = 0.01};
    EXPECT_DOUBLE_EQ(cuttingForce_N(0.004, params), 1.2);
    EXPECT_DOUBLE_EQ(cuttingForce_N(0.0, params), 0.3) << "a blade at the surface still opens a crack";
    EXPECT_DOUBLE_EQ(cuttingForce_N(0.05, params), 3.0) << "no deeper than the blade's edge";
    // The scalpel's threshold as a toughness: its whole edge in the tissue cuts with that force.
    EXPECT_DOUBLE_EQ(cuttingForce_N(kToughnessDepth_m, FractureParams{.toughness_J_per_m2 = toughnessFromThreshold(2)}),
                     2.0);
}

}  // namespace
}  // namespace hapticut::cutting
