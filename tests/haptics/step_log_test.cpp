// Step logs streamed through the writer's ring: the same bytes as the whole-log formatter for runs longer
// than the ring, an oriented recording that replays with its orientation, and no file left by a run
// that did not finish.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "hapticut/geometry/random_vec.h"
#include "hapticut/haptics/step_log.h"
#include "hapticut/haptics/trajectory.h"
#include "test_support.h"

namespace hapticut::haptics {
namespace {

namespace fs = std::filesystem;

using test::slurp;

std::vector<StepOutput> randomSteps(std::size_t count, int hands, bool oriented) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> n(0, 0.01);
    std::vector<StepOutput> steps(count);
    for (std::size_t i = 0; i < count; ++i) {
        StepOutput& s = steps[i];
        s.t_s = 1e-3 * static_cast<double>(i);
        s.handCount = hands;
        s.cut = rng() % 50 == 0;
        for (int h = 0; h < hands; ++h) {
            HandStep& hand = s.hands[static_cast<std::size_t>(h)];
            hand.device_m = randomVec3(n, rng);
            hand.proxy_m = randomVec3(n, rng);
            hand.force_N = 100 * randomVec3(n, rng);
            hand.contact = rng() % 2;
            hand.face = static_cast<std::uint32_t>(rng() % 10'000);
            hand.buttons = static_cast<std::uint32_t>(rng() % 2);
            hand.oriented = oriented;
            const Vec3 axis = randomVec3(n, rng);
            hand.orientation = Eigen::Quaterniond(1, axis.x(), axis.y(), axis.z()).normalized();
        }
    }
    return steps;
}

TEST(StepLogWriter, StreamsTheSameBytesAsTheWholeLogForRunsLongerThanItsRing) {
    for (const int hands : {1, 2}) {
        SCOPED_TRACE(hands);
        const std::vector<StepOutput> steps = randomSteps(3 * StepLogWriter::kRingSteps + 17, hands, false);
        test::ScratchDir dir;
        auto writer = StepLogWriter::open(
            {{dir / "force.csv", StepLogColumns::ForceLog}, {dir / "recording.csv", StepLogColumns::Recording}},
            StepLogWriter::WhenFull::Wait);
        ASSERT_TRUE(writer) << writer.error().toString();
        for (const StepOutput& s : steps) (*writer)->push(s);
        EXPECT_TRUE((*writer)->finish().empty());
        EXPECT_EQ((*writer)->rowsWritten(), static_cast<long>(steps.size()));
        EXPECT_EQ((*writer)->droppedSteps(), 0) << "simulated time waits for the disk instead";
        EXPECT_EQ(slurp(dir / "force.csv"), formatStepLog(steps, StepLogColumns::ForceLog));
        EXPECT_EQ(slurp(dir / "recording.csv"), formatStepLog(steps, StepLogColumns::Recording));
        EXPECT_FALSE(fs::exists(dir / "force.csv.tmp-hapticut"));
    }
}

TEST(StepLogWriter, ARecordingOfAnOrientedStylusReplaysWithItsOrientation) {
    const std::vector<StepOutput> steps = randomSteps(50, 1, true);
    test::ScratchDir dir;
    auto writer = StepLogWriter::open({{dir / "rec.csv", StepLogColumns::Recording}}, StepLogWriter::WhenFull::Wait);
    ASSERT_TRUE(writer);
    for (const StepOutput& s : steps) (*writer)->push(s);
    ASSERT_TRUE((*writer)->finish().empty());
    const std::string text = slurp(dir / "rec.csv");
    EXPECT_EQ(text.substr(0, text.find('\n')), "t,x,y,z,button,qw,qx,qy,qz,fx,fy,fz");
    const auto replay = readTrajectory(dir / "rec.csv");
    ASSERT_TRUE(replay) << replay.error().toString();
    ASSERT_EQ(replay->points.size(), steps.size());
    for (std::size_t i = 0; i < steps.size(); ++i) {
        EXPECT_TRUE(replay->points[i].sample.oriented);
        EXPECT_EQ(replay->points[i].sample.position_m, steps[i].hand().device_m);
        EXPECT_TRUE(replay->points[i].sample.orientation.isApprox(steps[i].hand().orientation, 1e-15));
    }
}

TEST(StepLogWriter, ARunThatDoesNotFinishLeavesTheTargetAsItWas) {
    test::ScratchDir dir;
    std::ofstream(dir / "force.csv") << "yesterday's log\n";
    {
        auto writer =
            StepLogWriter::open({{dir / "force.csv", StepLogColumns::ForceLog}}, StepLogWriter::WhenFull::Drop);
        ASSERT_TRUE(writer);
        for (const StepOutput& s : randomSteps(100, 1, false)) (*writer)->push(s);
    }  // destroyed without finish(): the run failed
    EXPECT_EQ(slurp(dir / "force.csv"), "yesterday's log\n");
    EXPECT_FALSE(fs::exists(dir / "force.csv.tmp-hapticut"));

    fs::create_directory(dir / "folder");
    const auto folder =
        StepLogWriter::open({{dir / "folder", StepLogColumns::ForceLog}}, StepLogWriter::WhenFull::Wait);
    ASSERT_FALSE(folder);
    EXPECT_EQ(folder.error().file, dir / "folder");
    EXPECT_NE(folder.error().message.find("is a folder"), std::string::npos) << folder.error().toString();
}

}  // namespace
}  // namespace hapticut::haptics
