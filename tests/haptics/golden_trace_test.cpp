// Golden force traces: the shipped trajectories replayed on the 1,619-triangle heart (pressed and
// stroked with the probe, cut with the scalpel) must give the checked-in force traces, so force
// feedback, the feel of cutting included, can never change silently. After an intended change,
// regenerate with HAPTICUT_UPDATE_GOLDEN=1 and review the diff like code.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "hapticut/common/line_reader.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/haptic_run.h"

namespace hapticut::scene {
namespace {

namespace fs = std::filesystem;
constexpr int kEvery = 10;  // keep every 10th step: 10 ms resolution is plenty to see a change

/// `cutThreshold_N`: the tool's; infinite for the probe, the scalpel's for a cut. Both tools' tips as
/// users get them (their footprints).
std::string traceOf(const std::string& trajectory_name, double cutThreshold_N) {
    const auto trajectory =
        haptics::readTrajectory(fs::path(HAPTICUT_SOURCE_DIR) / "assets/trajectories" / trajectory_name);
    EXPECT_TRUE(trajectory.has_value());
    const mesh::SurfaceMesh mesh = mesh::procedural::makeHeart({});
    cutting::CutModel organ(mesh, physics::buildModel(mesh, physics::Material{}));
    HapticRunConfig config;
    config.loop.cutThreshold_N = cutThreshold_N;
    config.loop.tipRadius_m =
        std::isfinite(cutThreshold_N) ? mesh::procedural::kScalpelTipRadius_m : mesh::procedural::kProbeTipRadius_m;
    config.keepSteps = 1'000'000;
    const auto run = runHaptic(organ, *trajectory, config);
    EXPECT_TRUE(run.has_value());
    if (!run) return {};
    const HapticRunResult& r = *run;
    std::string out = "t,fx,fy,fz,contact\n";
    for (std::size_t i = 0; i < r.keptSteps.size(); i += kEvery) {
        const haptics::StepOutput& s = r.keptSteps[i];
        char line[160];
        std::snprintf(line, sizeof line, "%.3f,%.9f,%.9f,%.9f,%d\n", s.t_s, s.hand().force_N.x(), s.hand().force_N.y(),
                      s.hand().force_N.z(), s.hand().contact ? 1 : 0);
        out += line;
    }
    return out;
}

void expectMatchesGolden(const std::string& trajectory_name,
                         double cutThreshold_N = std::numeric_limits<double>::infinity()) {
    const fs::path golden = fs::path(HAPTICUT_SOURCE_DIR) / "tests/data/golden" /
                            (fs::path(trajectory_name).stem().string() + ".forces.csv");
    const std::string actual = traceOf(trajectory_name, cutThreshold_N);
    if (std::getenv("HAPTICUT_UPDATE_GOLDEN")) {
        std::ofstream(golden) << actual;
        GTEST_SKIP() << "rewrote " << golden;
    }
    std::ifstream in(golden);
    ASSERT_TRUE(in) << "missing " << golden << ": run this test with HAPTICUT_UPDATE_GOLDEN=1";
    std::stringstream expected;
    expected << in.rdbuf();
    std::istringstream a(actual), e(expected.str());
    std::string la, le;
    int line = 0, compared = 0;
    double worst = 0;
    while (std::getline(e, le)) {
        ++line;
        ASSERT_TRUE(std::getline(a, la)) << "the trace ended early at line " << line;
        if (line == 1) continue;
        double ve[5], va[5];
        std::istringstream se(le), sa(la);
        std::string fe, fa;
        for (int k = 0; k < 5; ++k) {
            std::getline(se, fe, ',');
            std::getline(sa, fa, ',');
            ASSERT_TRUE(parseFiniteDouble(fe, ve[k]) && parseFiniteDouble(fa, va[k])) << "line " << line;
        }
        EXPECT_EQ(va[0], ve[0]) << "line " << line;
        EXPECT_EQ(va[4], ve[4]) << "contact differs at t = " << ve[0];
        // 1 mN: far below what a hand feels, far above floating-point noise between builds.
        for (int k = 1; k <= 3; ++k) EXPECT_NEAR(va[k], ve[k], 1e-3) << "force differs at t = " << ve[0];
        for (int k = 1; k <= 3; ++k) worst = std::max(worst, std::abs(va[k] - ve[k]));
        ++compared;
    }
    EXPECT_FALSE(std::getline(a, la)) << "the trace is longer than the golden one";
    EXPECT_GT(compared, 200);
    ::testing::Test::RecordProperty("worst_difference_N", std::to_string(worst));
}

TEST(GoldenTraces, PressOnTheFrontOfTheHeart) { expectMatchesGolden("press-front.csv"); }
TEST(GoldenTraces, StrokeAcrossTheFrontOfTheHeart) { expectMatchesGolden("stroke-front.csv"); }
// The scalpel's 4 cm cut across the front: the rupture, the blade's resistance while it cuts, the walls.
TEST(GoldenTraces, ScalpelCutAcrossTheFrontOfTheHeart) {
    expectMatchesGolden("cut-front.csv", mesh::procedural::kScalpelThreshold_N);
}

}  // namespace
}  // namespace hapticut::scene
