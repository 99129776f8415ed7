// Trajectory CSV: round trips, recordings that replay, interpolation, and clear errors.
#include <gtest/gtest.h>

#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/step_log.h"
#include "hapticut/haptics/trajectory.h"

#include "test_support.h"

namespace hapticut::haptics {
namespace {

TEST(Trajectory, RoundTripsWithoutOrientationAsOneWithout) {
    const auto t = parseTrajectory("t,x,y,z,button\n0,0,0,0.1,0\n0.5,0.01,0,0.05,1\n1.0,0.02,0,0.0,1\n", "path.csv");
    ASSERT_TRUE(t.has_value()) << t.error().toString();
    EXPECT_FALSE(t->points[0].sample.oriented);
    const std::string text = formatTrajectory(*t);
    EXPECT_EQ(text.substr(0, text.find('\n')), "t,x,y,z,button") << "no orientation columns to turn a blade";
    const auto again = parseTrajectory(text, "again.csv");
    ASSERT_TRUE(again.has_value()) << again.error().toString();
    ASSERT_EQ(again->points.size(), 3u);
    EXPECT_EQ(again->points[1].sample.position_m, Vec3(0.01, 0, 0.05));
    EXPECT_EQ(again->points[2].sample.buttons, 1u);
    EXPECT_FALSE(again->points[2].sample.oriented);
    EXPECT_DOUBLE_EQ(again->duration_s(), 1.0);
}

TEST(Trajectory, RoundTripsWithOrientation) {
    const auto t =
        parseTrajectory("t,x,y,z,button,qw,qx,qy,qz\n0,0,0,0.1,0,1,0,0,0\n1,0.02,0,0,1,0,0,0,1\n", "path.csv");
    ASSERT_TRUE(t.has_value()) << t.error().toString();
    const auto again = parseTrajectory(formatTrajectory(*t), "again.csv");
    ASSERT_TRUE(again.has_value()) << again.error().toString();
    for (const TrajectoryPoint& p : again->points) EXPECT_TRUE(p.sample.oriented);
    EXPECT_TRUE(again->points[1].sample.orientation.isApprox(Eigen::Quaterniond(0, 0, 0, 1)));
    // Replayed halfway, the stylus has turned halfway about z, and says it reports an orientation.
    ReplayDevice device(*again);
    const DeviceSample half = device.read(0.5);
    EXPECT_TRUE(half.oriented);
    EXPECT_NEAR(half.orientation.angularDistance(Eigen::Quaterniond::Identity()), 3.14159265358979 / 2, 1e-9);
}

TEST(Trajectory, ARecordingReplaysAsATrajectory) {
    std::vector<StepOutput> log(3);
    for (int i = 0; i < 3; ++i) {
        log[i].t_s = 0.001 * i;
        log[i].hands[0].device_m = Vec3(0, 0, 0.01 * i);
        log[i].hands[0].force_N = Vec3(0, 0, 0.5 * i);
        log[i].hands[0].buttons = 1;
    }
    const std::string text = formatStepLog(log, StepLogColumns::Recording);
    EXPECT_EQ(text.substr(0, text.find('\n')), "t,x,y,z,button,fx,fy,fz");
    const auto t = parseTrajectory(text, "recording.csv");
    ASSERT_TRUE(t.has_value()) << t.error().toString();
    EXPECT_EQ(t->points[2].sample.position_m, Vec3(0, 0, 0.02));
}

TEST(ReplayDevice, InterpolatesLinearlyAndHoldsTheEnds) {
    const auto t = parseTrajectory("t,x,y,z,button\n1.0,0,0,0,0\n2.0,0.1,0,0,1\n", "path.csv");
    ASSERT_TRUE(t.has_value());
    ReplayDevice device(*t);
    EXPECT_NEAR(device.read(0.25).position_m.x(), 0.025, 1e-15) << "time runs from the first sample";
    EXPECT_NEAR(device.read(0.25).velocity_m_per_s.x(), 0.1, 1e-12);
    EXPECT_EQ(device.read(-1).position_m.x(), 0.0);
    EXPECT_EQ(device.read(5).position_m.x(), 0.1);
    EXPECT_EQ(device.read(0.9).buttons, 1u);
    EXPECT_NEAR(device.read(0.1).position_m.x(), 0.01, 1e-15) << "going back in time works too";
}

TEST(Trajectory, ErrorsNameTheLineAndWhatWasExpected) {
    auto expectError = [](const std::string& text, int line, const std::string& fragment) {
        test::expectError(parseTrajectory(text, "path.csv"), line, fragment);
    };
    expectError("", 0, "file is empty");
    expectError("time,x,y,z,button\n", 1, "header column 1 should be 't'");
    expectError("t,x,y,z\n", 1, "expected the header 't,x,y,z,button'");
    expectError("t,x,y,z,button\n0,0,0,0,0\n0.1,0,zero,0,0\n", 3, "expected a finite number for y, found 'zero'");
    expectError("t,x,y,z,button\n0,0,0,0,0\n0.1,0,0,0\n", 3, "expected 5 comma-separated values, found 4");
    expectError("t,x,y,z,button\n0,0,0,0,0\n0,0,0,0,0\n", 3, "time must increase");
    expectError("t,x,y,z,button\n0,0,0,0,4\n0.1,0,0,0,0\n", 2, "button must be 0 or 1, or 2 and 3 with the second");
    expectError("t,x,y,z,button,tool\n0,0,0,0,0,1.5\n0.1,0,0,0,0,0\n", 2,
                "tool must be the index of one of the scene's");
    expectError("t,x,y,z,button,tool\n0,0,0,0,0,-1\n0.1,0,0,0,0,0\n", 2, "tool must be the index");
    expectError("t,x,y,z,button,tool,fx\n", 1, "header column 8 should be 'fy'");
    expectError("t,x,y,z,button,fx,fy,fz,tool\n", 1, "then by 'tool' and then by 'fx,fy,fz'");
    expectError("t,x,y,z,button,qw,qx\n", 1, "expected the header");
    expectError("t,x,y,z,button\n0,0,0,nan,0\n", 2, "expected a finite number for z");
    expectError("t,x,y,z,button\n0,0,0,0,0\n", 2, "at least two samples");
    expectError("t,x,y,z,button,qw,qx,qy,qz\n0,0,0,0,0,1e-12,0,0,0\n", 2, "zero length");
}

// A session's columns: the second button (a mark) and the tool in hand read back; a recording's forces
// after them are skipped; written out, the tool column comes back.
TEST(Trajectory, ASessionsMarksAndToolsReadBackAndWriteOut) {
    const auto session = parseTrajectory(
        "t,x,y,z,button,qw,qx,qy,qz,tool,fx,fy,fz\n0,0,0,0,1,1,0,0,0,0,0,0,0\n0.001,0,0,0,3,1,0,0,0,1,0.5,0,0\n",
        "s.csv");
    ASSERT_TRUE(session) << session.error().toString();
    ASSERT_EQ(session->points.size(), 2u);
    EXPECT_EQ(session->points[1].sample.buttons, 3u);
    EXPECT_EQ(session->points[0].tool, 0);
    EXPECT_EQ(session->points[1].tool, 1);
    EXPECT_TRUE(session->points[1].sample.oriented);
    const std::string text = formatTrajectory(*session);
    EXPECT_EQ(text.substr(0, text.find('\n')), "t,x,y,z,button,qw,qx,qy,qz,tool");
    const auto again = parseTrajectory(text, "again.csv");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->points[1].tool, 1);
    // A session's blade turned halfway: no orientation (0,0,0,0) before, one after, and so again when written.
    const auto turned =
        parseTrajectory("t,x,y,z,button,qw,qx,qy,qz\n0,0,0,0,1,0,0,0,0\n0.1,0,0,0,1,0,0,0,2\n", "t.csv");
    ASSERT_TRUE(turned) << turned.error().toString();
    EXPECT_FALSE(turned->points[0].sample.oriented);
    EXPECT_TRUE(turned->points[1].sample.oriented);
    EXPECT_DOUBLE_EQ(turned->points[1].sample.orientation.z(), 1.0) << "normalised";
    EXPECT_EQ(formatTrajectory(*turned), "t,x,y,z,button,qw,qx,qy,qz\n0,0,0,0,1,0,0,0,0\n0.1,0,0,0,1,0,0,0,1\n");
    const auto plain = parseTrajectory("t,x,y,z,button\n0,0,0,0,2\n0.1,0,0,0,0\n", "p.csv");
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->points[0].tool, -1) << "no tool column: none recorded";
}

}  // namespace
}  // namespace hapticut::haptics
