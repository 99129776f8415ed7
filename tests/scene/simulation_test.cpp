// A live simulation driven the way the viewer drives it, headless: its mice touch only while their button
// is held, so an idle second hand with a scalpel, a switch of hands, or a cursor jumping through the
// organ presses and cuts nothing; a held button presses and cuts.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "hapticut/geometry/aabb.h"
#include "hapticut/scene/bench_scenes.h"
#include "hapticut/scene/simulation.h"
#include "test_support.h"

namespace hapticut::scene {
namespace {

using namespace std::chrono_literals;

/// Lets the loop run on its own thread for `duration`, and returns the largest force either hand was
/// sent meanwhile, read from the snapshots as the viewer reads them.
double runFor(Simulation& simulation, std::chrono::milliseconds duration) {
    double maxForce = 0;
    const auto end = std::chrono::steady_clock::now() + duration;
    while (std::chrono::steady_clock::now() < end) {
        const haptics::Snapshot& s = simulation.loop().snapshots().readLatest();
        for (int h = 0; h < s.handCount; ++h)
            maxForce = std::max(maxForce, s.hands[static_cast<std::size_t>(h)].force_N.norm());
        std::this_thread::sleep_for(2ms);
    }
    return maxForce;
}

TEST(Simulation, AnIdleSecondHandAndASwitchOfHandsNeitherPressNorCut) {
    auto scene = loadScene({});
    ASSERT_TRUE(scene.has_value());
    Simulation simulation(std::move(*scene));
    simulation.setTool(1);  // the scalpel in the first hand
    simulation.setHandCount(2);
    EXPECT_LT(runFor(simulation, 300ms), 1e-9) << "before any input nothing touches the heart";
    simulation.setActiveHand(1);  // Tab
    EXPECT_LT(runFor(simulation, 200ms), 1e-9);
    EXPECT_EQ(simulation.loop().snapshots().readLatest().cutEvents, 0);
}

TEST(Simulation, TheMouseGoesThroughTheOrganWithTheButtonUpAndPressesWithItHeld) {
    auto scene = loadScene({});
    ASSERT_TRUE(scene.has_value());
    const geometry::Aabb box = geometry::boundsOf(scene->source.mesh.positions);
    const Vec3 front = frontVertex_m(scene->source.mesh, 0, -0.01);  // where the shipped cut starts
    Simulation simulation(std::move(*scene));
    simulation.setTool(1);
    haptics::VirtualDevice& mouse = simulation.mouseDevice();
    // A cursor jumping from in front of the heart to its centre and out behind, as a view change makes it.
    for (const Vec3& at : {Vec3(box.center().x(), box.center().y(), box.max.z() + 0.02), box.center(),
                           Vec3(box.center().x(), box.center().y(), box.min.z() - 0.02)}) {
        mouse.setPosition(at, 0);
        EXPECT_LT(runFor(simulation, 100ms), 1e-9);
    }
    EXPECT_EQ(simulation.loop().snapshots().readLatest().cutEvents, 0);
    // Held, from in front of the heart 15 mm into it and 1.5 cm across: it presses, past the scalpel's
    // threshold, and cuts.
    mouse.setPosition(front + Vec3(0, 0, 0.005), 0);
    runFor(simulation, 50ms);
    mouse.setPosition(front - Vec3(0, 0, 0.015), 1);
    // The force ramps in over the loop's first half second of steps, which a loaded machine under a
    // sanitizer takes longer to step: held until it is past the threshold, for up to 3 s.
    double pressed_N = runFor(simulation, 300ms);
    for (int wait = 0; wait < 9 && pressed_N <= 2.0; ++wait) pressed_N = std::max(pressed_N, runFor(simulation, 300ms));
    for (int i = 1; i <= 30; ++i) {
        mouse.setPosition(front + Vec3(0.0005 * i, 0, -0.015), 1);
        pressed_N = std::max(pressed_N, runFor(simulation, 15ms));
    }
#ifdef HAPTICUT_SANITIZED
    // Under ThreadSanitizer on a loaded machine the loop stalls, and each stall zeroes the force sent and
    // ramps it back in: a CI run sent 0.24 N at most while the blade cut. The cut below shows that the
    // blade passed the threshold; here it must press at all.
    constexpr double kLeastPressed_N = 0.1;
#else
    constexpr double kLeastPressed_N = 2.0;
#endif
    const haptics::Snapshot& pressed = simulation.loop().snapshots().readLatest();
    EXPECT_GT(pressed_N, kLeastPressed_N) << pressed.overruns << " overruns, " << pressed.stalls << " stalls";
    // Held there, the blade ahead of the crack cuts on. Two sanitized test programs at once on two cores
    // overran a thousand periods of the first thousand steps, and the stroke was over in a few dozen
    // steps before the cut had crossed an edge: held for up to 3 s more, as for the press.
    for (int wait = 0; wait < 10 && simulation.loop().snapshots().readLatest().cutEvents == 0; ++wait)
        runFor(simulation, 300ms);
    EXPECT_GT(simulation.loop().snapshots().readLatest().cutEvents, 0);
}

// The viewer's recording: every step of the loop (not one a frame), timed from 0 when it starts, with the
// force, and going on through a restart of the loop with its times continuing.
TEST(Simulation, ARecordingHasEveryStepOfTheLoopTimedFromZeroThroughARestart) {
    auto scene = loadScene({});
    ASSERT_TRUE(scene.has_value());
    const Vec3 front = frontVertex_m(scene->source.mesh, 0, -0.01);
    Simulation simulation(std::move(*scene));
    runFor(simulation, 100ms);  // the loop's own time is past 0 when the recording starts
    test::ScratchDir dir;
    const std::string file = (dir.path() / "session.csv").string();
    ASSERT_FALSE(simulation.startRecording(file).has_value());
    haptics::VirtualDevice& mouse = simulation.mouseDevice();
    mouse.setPosition(front + Vec3(0, 0, 0.01), 0);
    runFor(simulation, 150ms);
    mouse.setPosition(front - Vec3(0, 0, 0.004), 1);  // held: a press
    runFor(simulation, 100ms);
    mouse.setPosition(front - Vec3(0, 0, 0.004), 3);  // and a mark (the viewer's m, a stylus's second button)
    runFor(simulation, 50ms);
    simulation.restartLoop();  // a new integrator or rate chosen in the panel
    runFor(simulation, 200ms);
    EXPECT_TRUE(simulation.stopRecording().empty());
    EXPECT_FALSE(simulation.recording());

    std::ifstream in(file);
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line.rfind("t,x,y,z,button,qw,qx,qy,qz,tool,fx,fy,fz", 0), 0u) << line;
    std::vector<double> t;
    double maxForce_N = 0;
    long marked = 0;
    while (std::getline(in, line)) {
        std::vector<double> v;
        std::size_t at = 0;
        while (at <= line.size()) {
            const std::size_t comma = std::min(line.find(',', at), line.size());
            v.push_back(std::stod(line.substr(at, comma - at)));
            at = comma + 1;
        }
        ASSERT_EQ(v.size(), 13u) << line;
        t.push_back(v[0]);
        EXPECT_EQ(v[5] * v[5] + v[6] * v[6] + v[7] * v[7] + v[8] * v[8], 0) << "the mouse reports no orientation";
        EXPECT_EQ(v[9], 0) << "the first tool in hand";
        marked += v[4] == 3;
        maxForce_N = std::max(maxForce_N, std::hypot(v[10], v[11], v[12]));
    }
    // At least 40% of 500 ms of a 1 kHz loop even on a loaded machine: a display-rate recording has 30.
    ASSERT_GT(t.size(), 200u);
    EXPECT_LT(t.front(), 0.0015) << "times from the start of the recording";
    for (std::size_t i = 1; i < t.size(); ++i)
        ASSERT_NEAR(t[i] - t[i - 1], 0.001, 1e-9) << "row " << i << ": every step, one period apart, a restart too";
    EXPECT_GT(maxForce_N, 0.1) << "the press's force is recorded";
    EXPECT_GT(marked, 10) << "the mark is recorded as the second button";
}

}  // namespace
}  // namespace hapticut::scene
