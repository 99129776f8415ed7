// Two hands on one model, and the safety every hand's force passes: two devices pressing the heart at
// once (each gets its own force, the tissue feels both), a probe holding while a scalpel cuts, the
// force-rate limit, the device's rated stiffness, the ramp after a watchdog reset, zero force when the
// loop goes away (also by an exception); device names and the workspace fit.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "hapticut/haptics/device_name.h"
#include "hapticut/haptics/force_safety.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/haptics/workspace_fit.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"

namespace hapticut::haptics {
namespace {

struct Heart {
    mesh::SurfaceMesh mesh = mesh::procedural::makeHeart({});
    cutting::CutModel organ{mesh, physics::buildModel(mesh, physics::Material{})};
};

/// A loop that must build: the hands here are always valid.
std::unique_ptr<HapticLoop> makeLoop(cutting::CutModel& organ, std::span<const Hand> hands, LoopConfig config = {}) {
    auto loop = HapticLoop::create(organ, hands, config);
    EXPECT_TRUE(loop.has_value()) << loop.error().toString();
    return std::move(loop.value());
}

/// The front-most rest point of the heart near (x, y).
Vec3 frontAt(const mesh::SurfaceMesh& mesh, double x, double y) {
    Vec3 best(x, y, -1);
    for (const Vec3& p : mesh.positions)
        if (std::abs(p.x() - x) < 0.006 && std::abs(p.y() - y) < 0.006 && p.z() > best.z()) best = p;
    return best;
}

/// Out in front of `surface`, then `depth` into it by 0.8 s, held to the end.
Trajectory pressAt(const Vec3& surface, double depth, double end_s = 2.0) {
    Trajectory t;
    for (const auto& [time, z] : {std::pair{0.0, 0.03}, {0.6, 0.005}, {0.8, -depth}, {end_s, -depth}}) {
        TrajectoryPoint p;
        p.t_s = time;
        p.sample.position_m = surface + Vec3(0, 0, z);
        t.points.push_back(p);
    }
    return t;
}

/// A device with a stated maximum stiffness, placed by the test.
class RatedDevice final : public Device {
public:
    explicit RatedDevice(double maxStiffness) : maxStiffness_(maxStiffness) {}
    std::string_view name() const override { return "rated"; }
    DeviceSample read(double) override {
        DeviceSample s;
        s.position_m = position;
        return s;
    }
    void commandForce(const Vec3& f) override { force = f; }
    double maxForce_N() const override { return 10; }
    double maxStiffness_N_per_m() const override { return maxStiffness_; }
    Vec3 position = Vec3(0, 0, 1), force = Vec3::Zero();

private:
    double maxStiffness_;
};

TEST(TwoHands, BothPressTheHeartInTheSameStepAndEachFeelsItsOwnForce) {
    Heart h;
    const Vec3 right = frontAt(h.mesh, 0.012, 0.0), left = frontAt(h.mesh, -0.012, 0.005);
    ReplayDevice a(pressAt(right, 0.004)), b(pressAt(left, 0.008));
    const std::array<Hand, 2> hands{Hand{&a}, Hand{&b}};
    auto made = makeLoop(h.organ, hands);
    HapticLoop& loop = *made;
    ASSERT_EQ(loop.handCount(), 2);
    StepOutput last;
    Vec3 sentA, sentB;  // what the devices were told in the last step (the run's end zeroes them)
    runSimulated(loop, 1500, [&](const StepOutput& s) {
        last = s;
        sentA = a.lastForce();
        sentB = b.lastForce();
    });
    ASSERT_EQ(last.handCount, 2);
    const HandStep &ra = last.hands[0], &rb = last.hands[1];
    EXPECT_TRUE(ra.contact && rb.contact);
    EXPECT_GT(ra.force_N.z(), 0.3) << "the right hand is pushed back out of the front";
    EXPECT_GT(rb.force_N.z(), ra.force_N.z() + 0.3) << "the left hand presses twice as deep, and feels it";
    EXPECT_TRUE(sentA.isApprox(ra.force_N)) << "each device gets its own hand's force";
    EXPECT_TRUE(sentB.isApprox(rb.force_N));
    EXPECT_EQ(a.lastForce(), Vec3::Zero()) << "and zero once the run is over";
    // The tissue is dented under both tools.
    auto dent = [&](const Vec3& at) {
        double most = 0;
        const auto& x = h.organ.model().nodes;
        for (std::size_t i = 0; i < x.size(); ++i)
            if ((x.restPosition[i] - at).norm() < 0.005)
                most = std::max(most, x.restPosition[i].z() - x.position[i].z());
        return most;
    };
    EXPECT_GT(dent(right), 0.0015);
    EXPECT_GT(dent(left), 0.003);
    EXPECT_FALSE(loop.stats().watchdogTripped);
}

TEST(TwoHands, AProbeHoldsTheTissueWhileTheScalpelInTheOtherHandCuts) {
    Heart h;
    const Vec3 hold = frontAt(h.mesh, -0.015, -0.01);
    ReplayDevice probe(pressAt(hold, 0.006, 2.4));
    // The scalpel: down 12 mm in front at the right, then across to the centre.
    Trajectory cut;
    const Vec3 start = frontAt(h.mesh, 0.02, -0.01), end = frontAt(h.mesh, 0.0, -0.01);
    for (const auto& [time, p] : {std::pair{0.0, Vec3(start + Vec3(0, 0, 0.03))},
                                  {0.7, Vec3(start + Vec3(0, 0, 0.005))},
                                  {1.0, Vec3(start - Vec3(0, 0, 0.012))},
                                  {2.0, Vec3(end - Vec3(0, 0, 0.012))},
                                  {2.4, Vec3(end + Vec3(0, 0, 0.03))}}) {
        TrajectoryPoint q;
        q.t_s = time;
        q.sample.position_m = p;
        cut.points.push_back(q);
    }
    ReplayDevice scalpel(cut);
    const std::array<Hand, 2> hands{Hand{&probe}, Hand{&scalpel, mesh::procedural::kScalpelThreshold_N}};
    auto made = makeLoop(h.organ, hands);
    HapticLoop& loop = *made;
    double probeForceWhileCutting = std::numeric_limits<double>::infinity();
    runSimulated(loop, 2400, [&](const StepOutput& s) {
        if (s.cut) probeForceWhileCutting = std::min(probeForceWhileCutting, s.hands[0].force_N.norm());
    });
    EXPECT_GE(loop.stats().cutEvents, 3) << "the scalpel hand cut";
    EXPECT_GT(loop.cutter().stats().length_m, 0.008);
    EXPECT_GT(probeForceWhileCutting, 0.3) << "the probe kept holding the tissue through every cut event";
    for (const Vec3& p : h.organ.mesh().positions) EXPECT_TRUE(p.allFinite());
}

TEST(TwoHands, EachHandCanHaveItsOwnCouplingAndTheSofterOneFeelsTheSeriesSpring) {
    // The hand's spring k_h and the tissue k_t act in series: F = d / (1/k_h + 1/k_t), so halving k_h
    // lowers the force, but by less than half.
    auto holdForce = [](std::optional<double> coupling) {
        Heart h;
        ReplayDevice device(pressAt(frontAt(h.mesh, 0, 0), 0.003));
        Hand hand{&device};
        hand.couplingStiffness_N_per_m = coupling;
        auto made = makeLoop(h.organ, std::span<const Hand>(&hand, 1));
        double force = 0;
        runSimulated(*made, 1900, [&](const StepOutput& s) { force = s.hand().force_N.norm(); });
        return std::pair{force, made->couplingStiffness_N_per_m(0)};
    };
    const auto [own, ownK] = holdForce(200.0);
    const auto [loops, loopsK] = holdForce(std::nullopt);
    EXPECT_EQ(ownK, 200);
    EXPECT_EQ(loopsK, LoopConfig{}.couplingStiffness_N_per_m);
    EXPECT_GT(own, 0.1);
    EXPECT_LT(own, loops) << "a softer hand spring presses less";
    EXPECT_GT(own, 0.5 * loops) << "but the tissue's spring in series keeps it above half";

    Heart h;
    VirtualDevice a, b;
    Hand first{&a}, second{&b};
    first.couplingStiffness_N_per_m = 150;
    const std::array<Hand, 2> hands{first, second};
    auto made = makeLoop(h.organ, hands);
    made->commands().push({LoopCommand::Kind::SetCouplingStiffness, 250});
    made->step();
    EXPECT_EQ(made->couplingStiffness_N_per_m(0), 150) << "its own value is not the panel's";
    EXPECT_EQ(made->couplingStiffness_N_per_m(1), 250);
}

TEST(MouseHand, TouchesOnlyWhileItsButtonIsHeldSoAJumpingCursorNeitherPressesNorCuts) {
    Heart h;
    const Vec3 front = frontAt(h.mesh, 0, -0.01);
    VirtualDevice mouse;
    mouse.setPosition(front + Vec3(0, 0, 0.03));
    Hand hand{&mouse, mesh::procedural::kScalpelThreshold_N};
    hand.touchesOnlyWhileButtonHeld = true;
    auto made = makeLoop(h.organ, std::span<const Hand>(&hand, 1), LoopConfig{.rampTime_s = 0.01});
    HapticLoop& loop = *made;
    // Button up: the cursor jumps through the front, 15 mm in, and sweeps across inside the heart.
    double maxForce = 0;
    for (int i = 0; i < 400; ++i) {
        mouse.setPosition(front + Vec3(0.0001 * i - 0.02, 0, i < 10 ? 0.03 - 0.0045 * i : -0.015));
        const StepOutput s = loop.step();
        maxForce = std::max(maxForce, s.hand().force_N.norm());
        EXPECT_FALSE(s.hand().contact) << "step " << i;
        EXPECT_TRUE(s.hand().proxy_m.isApprox(s.hand().device_m)) << "let go, the proxy is where the device is";
    }
    EXPECT_EQ(maxForce, 0) << "hovering never presses";
    EXPECT_EQ(loop.stats().cutEvents, 0) << "nor cuts";

    // Out in front again, then the button held and the scalpel pushed 12 mm in and 24 mm across: it presses,
    // the surface gives way, and once the blade pulls hard enough (cutting/fracture.h) the cut runs.
    mouse.setPosition(front + Vec3(0, 0, 0.003));
    for (int i = 0; i < 20; ++i) loop.step();
    for (int i = 0; i < 600; ++i) {
        mouse.setPosition(front + Vec3(0.00004 * i, 0, 0.003 - std::min(i, 150) * 0.0001), 1);
        maxForce = std::max(maxForce, loop.step().hand().force_N.norm());
    }
    EXPECT_GT(maxForce, mesh::procedural::kScalpelThreshold_N) << "held, the hand presses";
    EXPECT_GT(loop.stats().cutEvents, 0) << "and the scalpel cuts";
    const long cutEvents = loop.stats().cutEvents;

    // Let go deep in the wound: the force drops at once and the cut ends, though the blade is still in.
    mouse.setPosition(front + Vec3(0.024, 0, -0.012), 0);
    const StepOutput released = loop.step();
    EXPECT_EQ(released.hand().force_N, Vec3::Zero());
    EXPECT_FALSE(loop.cutter().cutting());
    for (int i = 0; i < 200; ++i) loop.step();
    EXPECT_EQ(loop.stats().cutEvents, cutEvents) << "no cut while let go";
}

TEST(MouseHand, AnOrdinaryDeviceAtTheSamePlacePressesWithoutAButton) {
    // The flag is what keeps the mouse from pressing: a Phantom held in the tissue presses, button or not.
    Heart h;
    const Vec3 front = frontAt(h.mesh, 0, -0.01);
    VirtualDevice device;
    device.setPosition(front + Vec3(0, 0, 0.03));
    HapticLoop loop(h.organ, device, LoopConfig{.rampTime_s = 0.01});
    double maxForce = 0;
    for (int i = 0; i < 300; ++i) {
        device.setPosition(front + Vec3(0, 0, std::max(0.03 - 0.0002 * i, -0.006)));
        maxForce = std::max(maxForce, loop.step().hand().force_N.norm());
    }
    EXPECT_GT(maxForce, 1.0);
}

TEST(TwoHands, ALoopTakesOneOrTwoHandsWithDevices) {
    Heart h;
    VirtualDevice d;
    const auto noHands = HapticLoop::create(h.organ, std::span<const Hand>{});
    ASSERT_FALSE(noHands);
    EXPECT_NE(noHands.error().message.find("1 to 2 hands, not 0"), std::string::npos) << noHands.error().message;
    const std::array<Hand, 3> three{Hand{&d}, Hand{&d}, Hand{&d}};
    EXPECT_FALSE(HapticLoop::create(h.organ, three));
    const std::array<Hand, 1> none{Hand{nullptr}};
    const auto noDevice = HapticLoop::create(h.organ, none);
    ASSERT_FALSE(noDevice);
    EXPECT_EQ(noDevice.error().message, "a hand without a device");
    const std::array<Hand, 1> one{Hand{&d}};
    LoopConfig zeroRate;
    zeroRate.rate_hz = 0;
    EXPECT_FALSE(HapticLoop::create(h.organ, one, zeroRate)) << "a zero rate would divide every step by zero";
    EXPECT_TRUE(HapticLoop::create(h.organ, one));
}

TEST(ForceSafety, TheForceSentGrowsNoFasterThanTheHandsLimitAndEasesOffAtOnce) {
    EXPECT_TRUE(limitForceRate(Vec3::Zero(), Vec3(0, 0, 3), 0.5).isApprox(Vec3(0, 0, 0.5)));
    EXPECT_TRUE(limitForceRate(Vec3(0, 0, 2), Vec3(0, 0, 0.1), 0.5).isApprox(Vec3(0, 0, 0.1)))
        << "easing off is immediate";
    EXPECT_EQ(limitForceRate(Vec3(0, 0, 2), Vec3::Zero(), 0.5), Vec3::Zero()) << "so is letting go";
    EXPECT_TRUE(limitForceRate(Vec3(0, 0, 2), Vec3(0, 0, -1), 0.5).isApprox(Vec3(0, 0, 1.5))) << "a reversal ramps";
    EXPECT_TRUE(limitForceRate(Vec3(1, 0, 0), Vec3(1.2, 0, 0), 0.5).isApprox(Vec3(1.2, 0, 0)));

    // In the loop: a hand that jumps 1 cm into the heart in one step after the ramp.
    Heart h;
    RatedDevice device(std::numeric_limits<double>::infinity());
    const Vec3 front = frontAt(h.mesh, 0, 0);
    device.position = front + Vec3(0, 0, 0.002);
    Hand hand{&device};
    hand.maxForceRate_N_per_s = 500;  // 0.5 N per 1 ms step
    auto made = makeLoop(h.organ, std::span<const Hand>(&hand, 1));
    HapticLoop& loop = *made;
    runSimulated(loop, 600);
    device.position = front - Vec3(0, 0, 0.01);
    double previous = 0, largestRise = 0;
    runSimulated(loop, 20, [&](const StepOutput& s) {
        largestRise = std::max(largestRise, s.hand().force_N.norm() - previous);
        previous = s.hand().force_N.norm();
    });
    EXPECT_GT(previous, 1.2) << "the force got there";
    EXPECT_LE(largestRise, 0.5 + 1e-9);
    EXPECT_GE(loop.stats().rateLimitedSteps, 2) << "in steps of at most 0.5 N";
    device.position = front + Vec3(0, 0, 0.02);
    runSimulated(loop, 1);
    EXPECT_EQ(device.force, Vec3::Zero()) << "lifting the hand off drops the force at once";
}

TEST(ForceSafety, TheCouplingStaysBelowTheDevicesRatedStiffnessAtTheLoopRate) {
    EXPECT_DOUBLE_EQ(stiffnessCapAt(300, 1000), 300);
    EXPECT_DOUBLE_EQ(stiffnessCapAt(300, 4000), 300);
    EXPECT_DOUBLE_EQ(stiffnessCapAt(300, 500), 150);
    EXPECT_TRUE(std::isinf(stiffnessCapAt(0, 1000))) << "no rating, no cap";

    Heart h;
    RatedDevice device(150);
    const Vec3 front = frontAt(h.mesh, 0, 0);
    device.position = front + Vec3(0, 0, 0.02);
    HapticLoop loop(h.organ, device, {});
    EXPECT_DOUBLE_EQ(loop.couplingStiffness_N_per_m(0), 150) << "400 N/m asked for, 150 N/m rated";
    runSimulated(loop, 600);
    device.position = front - Vec3(0, 0, 0.004);
    StepOutput last;
    runSimulated(loop, 800, [&](const StepOutput& s) { last = s; });
    const double stretch = (last.hand().proxy_m - last.hand().device_m).norm();
    ASSERT_GT(stretch, 1e-3);
    EXPECT_NEAR(last.hand().force_N.norm() / stretch, 150, 15) << "the force reads the capped stiffness";
}

TEST(ForceSafety, AfterAWatchdogResetForcesFadeInAgain) {
    Heart h;
    RatedDevice device(std::numeric_limits<double>::infinity());
    const Vec3 front = frontAt(h.mesh, 0, 0);
    device.position = front + Vec3(0, 0, 0.02);
    HapticLoop loop(h.organ, device, {});
    runSimulated(loop, 600);
    device.position = front - Vec3(0, 0, 0.004);
    StepOutput out;
    runSimulated(loop, 500, [&](const StepOutput& s) { out = s; });
    const double steady = out.hand().force_N.norm();
    ASSERT_GT(steady, 0.4);
    device.position = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
    runSimulated(loop, 1, [&](const StepOutput& s) { out = s; });
    EXPECT_TRUE(loop.stats().watchdogTripped);
    EXPECT_EQ(device.force, Vec3::Zero());
    device.position = front - Vec3(0, 0, 0.004);
    runSimulated(loop, 50, [&](const StepOutput& s) { out = s; });
    EXPECT_EQ(out.hand().force_N, Vec3::Zero()) << "latched until someone resets it";
    ASSERT_TRUE(loop.commands().push({LoopCommand::Kind::ResetWatchdog, 0}));
    runSimulated(loop, 2, [&](const StepOutput& s) { out = s; });
    EXPECT_LT(out.hand().force_N.norm(), 0.05 * steady) << "not the full force at once";
    runSimulated(loop, 600, [&](const StepOutput& s) { out = s; });
    EXPECT_NEAR(out.hand().force_N.norm(), steady, 0.1 * steady) << "but all of it after the ramp";
}

TEST(ForceSafety, TheLoopLeavesEveryHandAtZeroForceWhenItGoesAwayEvenByAnException) {
    Heart h;
    RatedDevice a(std::numeric_limits<double>::infinity()), b(std::numeric_limits<double>::infinity());
    const Vec3 front = frontAt(h.mesh, 0, 0);
    a.position = b.position = front + Vec3(0, 0, 0.02);
    try {
        const std::array<Hand, 2> hands{Hand{&a}, Hand{&b}};
        auto made = makeLoop(h.organ, hands);
        HapticLoop& loop = *made;
        runSimulated(loop, 600);
        a.position = front - Vec3(0, 0, 0.004);
        b.position = frontAt(h.mesh, 0.01, 0) - Vec3(0, 0, 0.004);
        RealTimeScheduler clock(loop);
        ASSERT_FALSE(clock.start());
        // Watched through the snapshots: the devices' own fields belong to the loop's thread while it runs.
        auto pressing = [&] {
            const Snapshot& s = loop.snapshots().readLatest();
            return s.hands[0].force_N.norm() >= 0.5 && s.hands[1].force_N.norm() >= 0.5;
        };
        for (int i = 0; i < 500 && !pressing(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        clock.stop();
        // Pushing again, on the caller's thread this time, then something throws mid-run.
        runSimulated(loop, 100, [&](const StepOutput& s) {
            if (s.hands[0].force_N.norm() > 0.5 && s.hands[1].force_N.norm() > 0.5) throw std::runtime_error("mid-run");
        });
        FAIL() << "both hands should have been pushing";
    } catch (const std::runtime_error&) {}
    EXPECT_EQ(a.force, Vec3::Zero());
    EXPECT_EQ(b.force, Vec3::Zero());
}

TEST(DeviceName, ParsesEveryBackendAndSaysWhatIsWrongWithTheRest) {
    const auto virt = parseDeviceName("virtual");
    ASSERT_TRUE(virt);
    EXPECT_EQ(virt->kind, DeviceKind::Virtual);
    const auto replay = parseDeviceName("replay:paths/cut front.csv");
    ASSERT_TRUE(replay);
    EXPECT_EQ(replay->kind, DeviceKind::Replay);
    EXPECT_EQ(replay->argument, "paths/cut front.csv");
    EXPECT_EQ(replay->toString(), "replay:paths/cut front.csv");
    const auto touch = parseDeviceName("openhaptics:Left Touch");
    ASSERT_TRUE(touch);
    EXPECT_EQ(touch->kind, DeviceKind::OpenHaptics);
    EXPECT_EQ(touch->argument, "Left Touch");
    EXPECT_TRUE(parseDeviceName("openhaptics")->argument.empty());
    EXPECT_EQ(parseDeviceName("sdl:1")->argument, "1");
    EXPECT_EQ(parseDeviceName("sdl")->kind, DeviceKind::Sdl);
    for (const char* bad : {"", "phantom", "replay", "replay:", "sdl:one", "sdl:-1", "virtual:2", "openhaptics:"}) {
        const auto r = parseDeviceName(bad);
        ASSERT_FALSE(r) << bad;
        EXPECT_NE(r.error().message.find("expected virtual, replay:FILE, openhaptics[:NAME] or sdl[:INDEX]"),
                  std::string::npos)
            << r.error().message;
    }
    EXPECT_NE(parseDeviceName("sdl:one").error().message.find("whole number"), std::string::npos);
}

TEST(WorkspaceFit, TheDevicesReachCoversTheModelWithItsMarginAtOneScale) {
    const geometry::Aabb touch{Vec3(-80, -60, -35), Vec3(80, 60, 35)};              // millimetres
    const geometry::Aabb heart{Vec3(-0.04, -0.05, -0.03), Vec3(0.04, 0.05, 0.03)};  // metres
    const WorkspaceTransform w = fitWorkspace(touch, heart, 0.2);
    // The tightest axis decides: z, 6 cm x 1.4 over 70 mm.
    EXPECT_NEAR(w.scale, 0.06 * 1.4 / 70, 1e-12);
    EXPECT_TRUE(w.toScene(touch.center()).isApprox(heart.center()));
    geometry::Aabb mapped;
    for (int c = 0; c < 8; ++c) mapped.grow(w.toScene(Vec3(c & 1 ? 80 : -80, c & 2 ? 60 : -60, c & 4 ? 35 : -35)));
    for (int k = 0; k < 3; ++k) {
        EXPECT_LE(mapped.min[k], heart.min[k] - 0.2 * heart.extent()[k] + 1e-12) << k;
        EXPECT_GE(mapped.max[k], heart.max[k] + 0.2 * heart.extent()[k] - 1e-12) << k;
    }
    // Turned a quarter about y, the device's x spans the scene's z.
    const Eigen::Quaterniond quarter(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()));
    const WorkspaceTransform turned = fitWorkspace(touch, heart, 0.2, quarter);
    EXPECT_NEAR(turned.scale, 0.08 * 1.4 / 70, 1e-12) << "x of the scene now meets the device's 70 mm z";
    EXPECT_TRUE(turned.toScene(touch.center()).isApprox(heart.center()));
    EXPECT_TRUE(turned.forceToDevice(Vec3(0, 0, 1)).isApprox(Vec3(-1, 0, 0), 1e-12) ||
                turned.forceToDevice(Vec3(0, 0, 1)).isApprox(Vec3(1, 0, 0), 1e-12));
    EXPECT_DOUBLE_EQ(fitWorkspace(geometry::Aabb{}, heart).scale, 1) << "nothing to fit: identity";
}

}  // namespace
}  // namespace hapticut::haptics
