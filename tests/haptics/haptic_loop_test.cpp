// The haptic loop with real physics: pressing the heart indents it near the contact and it recovers;
// force along the outward normal growing with depth up to the clamp; the proxy never inside the
// deforming surface; the tissue gets exactly -F; ramp-in; watchdog; a real-time thread.
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "hapticut/collision/point_inside.h"
#include "hapticut/geometry/random_vec.h"
#include "hapticut/geometry/triangle_queries.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/haptic_run.h"
#include "test_support.h"

namespace hapticut::haptics {
namespace {

struct HeartScene {
    mesh::SurfaceMesh mesh = mesh::procedural::makeHeart({});
    cutting::CutModel organ{mesh, physics::buildModel(mesh, physics::Material{})};
    physics::MassSpringModel& model = organ.model();
};

/// The front-most surface point of the heart near the centre line: the probe target.
Vec3 frontPoint(const HeartScene& h) {
    Vec3 best = h.mesh.positions[0];
    for (const Vec3& p : h.mesh.positions)
        if (std::abs(p.x()) < 0.01 && std::abs(p.y()) < 0.01 && p.z() > best.z()) best = p;
    return best;
}

/// Approach the front along -z from 3 cm out, press `depth` in, hold, retract, rest.
Trajectory pressTrajectory(const Vec3& surface, double depth) {
    Trajectory t;
    auto add = [&](double time, double z) {
        TrajectoryPoint p;
        p.t_s = time;
        p.sample.position_m = Vec3(surface.x(), surface.y(), z);
        t.points.push_back(p);
    };
    add(0.0, surface.z() + 0.03);
    add(0.6, surface.z() + 0.005);  // still free after the 0.5 s force ramp
    add(1.0, surface.z() - depth);
    add(1.4, surface.z() - depth);
    add(1.6, surface.z() + 0.03);
    add(3.0, surface.z() + 0.03);
    return t;
}

TEST(HapticLoop, PressingTheHeartIndentsItNearTheContactAndItRecovers) {
    HeartScene h;
    const Vec3 front = frontPoint(h);
    ReplayDevice device(pressTrajectory(front, 0.004));
    HapticLoop loop(h.organ, device);
    double maxForce = 0, forceAtHold = 0;
    runSimulated(loop, 3000, [&](const StepOutput& s) {
        // The proxy is never inside the deforming heart (independent ray-parity test).
        EXPECT_FALSE(collision::insideClosedSurface(loop.bvh(), loop.surface(), s.hand().proxy_m)) << "t = " << s.t_s;
        if (s.t_s < 0.55) {
            EXPECT_EQ(s.hand().force_N, Vec3::Zero()) << "free space, t = " << s.t_s;
        }
        maxForce = std::max(maxForce, s.hand().force_N.norm());
        if (std::abs(s.t_s - 1.2) < 1e-9) {
            forceAtHold = s.hand().force_N.norm();
            EXPECT_GT(s.hand().force_N.z(), 0.9 * s.hand().force_N.norm()) << "pushes back along the outward normal";
            // Indented near the contact, not far away.
            double indent = 0;
            for (std::uint32_t n : h.mesh.faces[s.hand().face])
                indent = std::max(indent, (h.model.nodes.restPosition[n] - h.model.nodes.position[n]).z());
            EXPECT_GT(indent, 1e-3);
            double far = 0;
            for (std::size_t i = 0; i < h.model.nodes.size(); ++i)
                if (h.model.nodes.restPosition[i].z() < -0.01)
                    far = std::max(far, (h.model.nodes.position[i] - h.model.nodes.restPosition[i]).norm());
            EXPECT_LT(far, 1e-4) << "the back of the heart hardly moves";
        }
    });
    EXPECT_GT(forceAtHold, 0.5);
    EXPECT_LE(maxForce, kDefaultMaxForce_N + 1e-12);
    EXPECT_EQ(loop.stats().steps, 3000);
    EXPECT_GT(loop.stats().contactSteps, 300);
    EXPECT_LT(physics::maxDisplacement(h.model), 1e-4) << "recovered 1.4 s after release";
    EXPECT_EQ(device.lastForce(), Vec3::Zero()) << "no force is left on the device at the end";
}

TEST(HapticLoop, ForceGrowsWithDepthUpToTheClamp) {
    double previous = 0;
    bool clamped = false;
    for (double depth : {0.001, 0.002, 0.004, 0.008, 0.016, 0.03}) {
        HeartScene h;
        ReplayDevice device(pressTrajectory(frontPoint(h), depth));
        HapticLoop loop(h.organ, device);
        double atHold = 0;
        runSimulated(loop, 1250, [&](const StepOutput& s) {
            if (std::abs(s.t_s - 1.2) < 1e-9) atHold = s.hand().force_N.norm();
        });
        EXPECT_GE(atHold, previous - 1e-9) << "depth " << depth;
        EXPECT_LE(atHold, kDefaultMaxForce_N + 1e-12);
        clamped |= std::abs(atHold - kDefaultMaxForce_N) < 1e-9;
        previous = atHold;
    }
    EXPECT_TRUE(clamped) << "a deep press reaches the device's maximum force";
}

TEST(HapticLoop, ForceRampsInOverHalfASecond) {
    // With the physics paused the tissue cannot yield, so the force is the ramp times k_h times depth.
    HeartScene h;
    VirtualDevice device;
    device.setPosition(frontPoint(h) - Vec3(0, 0, 0.002));  // pressed in from the start
    HapticLoop loop(h.organ, device);
    ASSERT_TRUE(loop.commands().push({LoopCommand::Kind::Pause, 0}));
    std::vector<double> force;
    runSimulated(loop, 700, [&](const StepOutput& s) { force.push_back(s.hand().force_N.norm()); });
    EXPECT_EQ(force[0], 0.0);
    EXPECT_NEAR(force[100], 0.2 * force[600], 1e-9);
    EXPECT_NEAR(force[250], 0.5 * force[600], 1e-9);
    EXPECT_NEAR(force[600], force[699], 1e-12);
    EXPECT_NEAR(force[600], 400 * 0.002, 0.1) << "k_h times depth, give or take where the proxy touches";
}

/// A device that reports NaN from a given step on.
class FaultyDevice final : public Device {
public:
    explicit FaultyDevice(Vec3 at) : at_(at) {}
    std::string_view name() const override { return "faulty"; }
    DeviceSample read(double t) override {
        DeviceSample s;
        s.position_m = t > 0.7 ? Vec3::Constant(std::nan("")) : at_;
        return s;
    }
    void commandForce(const Vec3& f) override { last = f; }
    double maxForce_N() const override { return kDefaultMaxForce_N; }
    Vec3 last = Vec3::Zero();

private:
    Vec3 at_;
};

TEST(HapticLoop, WatchdogZeroesTheForceOnANonFiniteValue) {
    HeartScene h;
    FaultyDevice device(frontPoint(h) - Vec3(0, 0, 0.003));
    HapticLoop loop(h.organ, device);
    double before = 0, after = 0;
    runSimulated(loop, 690, [&](const StepOutput& s) { before = s.hand().force_N.norm(); });
    EXPECT_GT(before, 0.3) << "pressing before the fault";
    runSimulated(loop, 50, [&](const StepOutput& s) {
        if (s.t_s > 0.7) after = std::max(after, s.hand().force_N.norm());
    });
    EXPECT_EQ(after, 0.0);
    EXPECT_TRUE(loop.stats().watchdogTripped);
    EXPECT_GT(loop.stats().nonFiniteEvents, 0);
    EXPECT_EQ(device.last, Vec3::Zero());
    EXPECT_TRUE(physics::allFinite(h.model)) << "the fault never reached the tissue";
    EXPECT_TRUE(loop.proxy().position().allFinite()) << "nor the proxy";
}

TEST(HapticLoop, RunsInItsOwnThreadAtTheConfiguredRate) {
    HeartScene h;
    VirtualDevice device;
    device.setPosition(frontPoint(h) + Vec3(0, 0, 0.01));
    HapticLoop loop(h.organ, device);
    long observed = 0;
    RealTimeScheduler clock(loop);
    ASSERT_FALSE(clock.start(300, [&](const StepOutput&) { ++observed; }));
    // Move the device in from this thread while the loop runs: the force appears.
    for (int i = 0; i < 100; ++i) {
        device.setPosition(frontPoint(h) + Vec3(0, 0, 0.01 - 0.00015 * i));
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    while (clock.running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    clock.stop();
    EXPECT_EQ(loop.stats().steps, 300);
    EXPECT_EQ(observed, 300);
    EXPECT_EQ(loop.stats().periodError_us.count(), 300u);
    EXPECT_GT(loop.stats().wallTime_s, 0.29) << "paced by the wall clock, not as fast as possible";
    EXPECT_EQ(device.lastForce(), Vec3::Zero()) << "zero force after the loop ends";
    const Snapshot& snap = loop.snapshots().readLatest();
    EXPECT_EQ(snap.positions.size(), h.model.nodes.size());
    EXPECT_GT(snap.step, 0);
}

// Steps held up for 30 ms each (an organ far too large to step in a period): the period error says so,
// past the histogram's fine range, instead of showing the schedule restarted after each stall.
TEST(HapticLoop, PeriodErrorStaysHonestWhenEveryStepIsLate) {
    HeartScene h;
    VirtualDevice device;
    device.setPosition(frontPoint(h) + Vec3(0, 0, 0.01));
    HapticLoop loop(h.organ, device);
    RealTimeScheduler clock(loop);
    ASSERT_FALSE(clock.start(8, [](const StepOutput&) { std::this_thread::sleep_for(std::chrono::milliseconds(30)); }));
    while (clock.running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    clock.stop();
    const Summary late = loop.stats().periodError_us.summary();
    EXPECT_EQ(late.count, 8u);
    EXPECT_GT(late.p50, 25'000) << "each step after the first started about 29 ms late";
    EXPECT_GT(late.max, 25'000);
}

// The stepping thread asks for real-time scheduling and runs as scheduling() says: under SCHED_FIFO at
// the configured priority where the process may (root, CAP_SYS_NICE, an rtprio limit), else normally
// with the refusal's reason; with priority 0 it asks for nothing.
TEST(HapticLoop, TheSteppingThreadIsScheduledAsItsReportSays) {
    HeartScene h;
    VirtualDevice device;
    device.setPosition(frontPoint(h) + Vec3(0, 0, 0.01));
    for (const int priority : {40, 0}) {
        LoopConfig config;
        config.hapticThreadPriority = priority;
        HapticLoop loop(h.organ, device, config);
        std::atomic<int> policy{-1}, fifoPriority{-1};
        RealTimeScheduler clock(loop);
        ASSERT_FALSE(clock.start(20, [&](const StepOutput&) {
            sched_param param{};
            int p = -1;
            pthread_getschedparam(pthread_self(), &p, &param);
            policy = p, fifoPriority = param.sched_priority;
        }));
        while (clock.running()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        clock.stop();
        const std::string scheduling = clock.scheduling();
        if (priority == 0) {
            EXPECT_EQ(scheduling, "normal");
            EXPECT_EQ(policy, SCHED_OTHER);
        } else if (scheduling == "SCHED_FIFO 40") {
            EXPECT_EQ(policy, SCHED_FIFO);
            EXPECT_EQ(fifoPriority, 40);
        } else {
            EXPECT_EQ(scheduling.rfind("normal: SCHED_FIFO 40 refused (", 0), 0u) << scheduling;
            EXPECT_EQ(policy, SCHED_OTHER);
        }
    }
}

// A loop under SCHED_FIFO whose every step comes too late (its observer holds it up 1.5 ms a period)
// would never sleep and starve the machine's other threads: after a window of such steps it goes back
// to the normal scheduler.
TEST(HapticLoop, ASteppingThreadWithNoTimeToSleepLeavesRealtimeScheduling) {
    HeartScene h;
    VirtualDevice device;
    device.setPosition(frontPoint(h) + Vec3(0, 0, 0.01));
    HapticLoop loop(h.organ, device);
    std::atomic<int> firstPolicy{-1}, lastPolicy{-1};
    RealTimeScheduler clock(loop);
    ASSERT_FALSE(clock.start(kSchedulingWindowSteps + 20, [&](const StepOutput& s) {
        sched_param param{};
        int p = -1;
        pthread_getschedparam(pthread_self(), &p, &param);
        if (s.t_s == 0) firstPolicy = p;
        lastPolicy = p;
        std::this_thread::sleep_for(std::chrono::microseconds(1500));
    }));
    while (clock.running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    clock.stop();
    if (firstPolicy != SCHED_FIFO) GTEST_SKIP() << "this process may not schedule threads in real time";
    EXPECT_EQ(clock.scheduling(), "normal: SCHED_FIFO 40 left when more than half of " +
                                      std::to_string(kSchedulingWindowSteps) + " steps had no time to sleep");
    EXPECT_EQ(lastPolicy, SCHED_OTHER);
}

// A stall of the loop's own thread (here its observer held up once for 60 ms, as a process stopped
// and resumed would be): every missed period counts as an overrun, and the step after it sends no
// force, which then ramps back in rather than jumping to where the hand has since gone.
TEST(HapticLoop, AStallOfItsOwnThreadCountsEveryMissedPeriodAndTheForceRampsBackIn) {
    HeartScene h;
    VirtualDevice device;
    device.setPosition(frontPoint(h) - Vec3(0, 0, 0.002));
    LoopConfig config;
    config.rampTime_s = 0.05;
    config.stallRampTime_s = 0.05;
    HapticLoop loop(h.organ, device, config);
    std::vector<double> force(600, -1);
    long stalledAt = -1;
    RealTimeScheduler clock(loop);
    ASSERT_FALSE(clock.start(600, [&](const StepOutput& s) {
        const auto i = static_cast<std::size_t>(std::lround(s.t_s * 1000));
        force[i] = s.hand().force_N.norm();
        if (i == 300) std::this_thread::sleep_for(std::chrono::milliseconds(60));
        if (i == 301) stalledAt = 301;
    }));
    while (clock.running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    clock.stop();
    const LoopStats& st = loop.stats();
    EXPECT_GE(st.stalls, 1);
    EXPECT_GE(st.missedPeriods, 55) << "60 ms held up: about 59 periods without a step";
    EXPECT_GE(st.overruns, st.missedPeriods);
    ASSERT_EQ(stalledAt, 301);
    EXPECT_EQ(force[301], 0.0) << "the step after the stall sends nothing";
    // The ramp's shape, when this was the run's only stall (a sanitizer's build may stall more often).
    if (st.stalls == 1) {
        EXPECT_GT(force[299], 0.3) << "pressing before the stall";
        EXPECT_LT(force[311], 0.5 * force[299]) << "and the force ramps back in over 50 ms";
        EXPECT_NEAR(force[599], force[299], 0.1 * force[299]) << "to the same press";
    }
    EXPECT_EQ(loop.snapshots().readLatest().stalls, st.stalls) << "the panel shows them";
}

// Snapshots copy only what moved since each slot was last written: read now and then, as a renderer
// does, so that slots fall several snapshots behind, every one still shows the tissue exactly.
TEST(HapticLoop, SnapshotsShowTheTissueExactlyThoughTheyCopyOnlyWhatMoved) {
    HeartScene h;
    VirtualDevice device;
    HapticLoop loop(h.organ, device);
    int checked = 0;
    double pressed = 0;
    for (int i = 0; i < 1200; ++i) {
        const double depth = 0.004 * std::sin(i * 0.004);  // in and out, so nodes move, rest and move again
        device.setPosition(frontPoint(h) + Vec3(0.002 * std::sin(i * 0.01), 0, 0.001 - depth));
        loop.step();
        pressed = std::max(pressed, physics::maxDisplacement(h.model));
        if (i % 8 == 0 && (i / 8) % 3 != 1) {  // just after a snapshot, reading two in three
            const Snapshot& snap = loop.snapshots().readLatest();
            ASSERT_EQ(snap.positions.size(), h.model.nodes.size());
            for (std::size_t k = 0; k < snap.positions.size(); ++k)
                ASSERT_EQ(snap.positions[k], h.model.nodes.position[k]) << "node " << k << " at step " << i;
            ++checked;
        }
    }
    EXPECT_GT(checked, 90);
    EXPECT_GT(pressed, 1e-3);
    EXPECT_GT(loop.stats().contactSteps, 200);
}

// The collision tree refits only the nodes that moved out of their boxes' margin: every query on the
// pressed, released and pressed-again heart still matches brute force over the surface as it is, with
// the physics in the loop's thread and on its own (multi-rate, stepped in simulated time).
TEST(HapticLoop, TheCollisionTreeHoldsTheMovingSurfaceThoughItRefitsOnlyWhatLeftItsBoxes) {
    for (const LoopConfig::PhysicsRate rate : {LoopConfig::PhysicsRate::Single, LoopConfig::PhysicsRate::Multi}) {
        HeartScene h;
        VirtualDevice device;
        LoopConfig config;
        config.physicsRate = rate;
        HapticLoop loop(h.organ, device, config);
        ASSERT_EQ(loop.multiRate(), rate == LoopConfig::PhysicsRate::Multi);
        ASSERT_GT(loop.bvh().margin(), 0);
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> near(-0.004, 0.004);
        int checked = 0;
        double pressed = 0;
        for (int i = 0; i < 1200; ++i) {
            const double depth = 0.006 * std::sin(i * 0.004);
            const Vec3 target = frontPoint(h) + Vec3(0.002 * std::sin(i * 0.01), 0, 0.001 - depth);
            device.setPosition(target);
            loop.step();
            pressed = std::max(pressed, physics::maxDisplacement(h.model));
            if (i % 10 != 0) continue;
            const collision::SurfaceView now = loop.surface();
            for (int q = 0; q < 20; ++q) {
                const Vec3 p = target + randomVec3(near, rng);
                double brute = 1e300;
                for (const mesh::Face& f : now.faces)
                    brute = std::min(brute, (geometry::closestPointOnTriangle(p, now.positions[f[0]],
                                                                              now.positions[f[1]], now.positions[f[2]])
                                                 .point -
                                             p)
                                                .norm());
                const auto closest = loop.bvh().closestPoint(now, p);
                ASSERT_TRUE(closest) << "step " << i;
                ASSERT_NEAR(closest->distance, brute, 1e-15) << "step " << i;
                const double dy = near(rng);  // y first, as the seed's segments were drawn (random_vec.h)
                const Vec3 to = p + 0.01 * Vec3(near(rng), dy, -0.004).normalized();
                std::optional<double> first;
                for (const mesh::Face& f : now.faces)
                    if (const auto hit = geometry::intersectSegmentTriangle(p, to, now.positions[f[0]],
                                                                            now.positions[f[1]], now.positions[f[2]]))
                        first = std::min(first.value_or(2.0), hit->t);
                const auto hit = loop.bvh().firstHit(now, p, to);
                ASSERT_EQ(hit.has_value(), first.has_value()) << "step " << i;
                if (hit) {
                    ASSERT_DOUBLE_EQ(hit->t, *first) << "step " << i;
                }
            }
            ++checked;
        }
        EXPECT_EQ(checked, 120);
        EXPECT_GT(pressed, 2e-3) << "the heart was pressed millimetres deep: its nodes left their boxes";
    }
}

TEST(HapticLoop, CommandsReachTheLoop) {
    HeartScene h;
    VirtualDevice device;
    device.setPosition(frontPoint(h) - Vec3(0, 0, 0.002));
    HapticLoop loop(h.organ, device);
    double before = 0, after = 1;
    runSimulated(loop, 600, [&](const StepOutput& s) { before = s.hand().force_N.norm(); });
    ASSERT_TRUE(loop.commands().push({LoopCommand::Kind::SetMaxForceScale, 0.0}));
    runSimulated(loop, 1, [&](const StepOutput& s) { after = s.hand().force_N.norm(); });
    EXPECT_GT(before, 0.1);
    EXPECT_EQ(after, 0.0);
}

TEST(VirtualDevice, FollowsAJumpingInputWithAFirstOrderLag) {
    VirtualDevice device;
    device.setFollowTime(0.01);
    device.setPosition(Vec3::Zero());
    device.read(0);
    device.setPosition(Vec3(0.01, 0, 0));  // a cursor's jump between two frames
    const DeviceSample first = device.read(0.001);
    EXPECT_NEAR(first.position_m.x(), 0.001, 1e-12);     // a tenth of the way after a tenth of the time constant
    EXPECT_NEAR(first.velocity_m_per_s.x(), 1.0, 1e-9);  // not the 10 m/s of the jump itself
    double x = first.position_m.x();
    for (int i = 2; i <= 100; ++i) x = device.read(i * 0.001).position_m.x();
    EXPECT_NEAR(x, 0.01, 0.01 * std::pow(0.9, 100) + 1e-12);  // 0.9 per step: there within a few time constants
    VirtualDevice jumping;
    jumping.setPosition(Vec3::Zero());
    jumping.read(0);
    jumping.setPosition(Vec3(0.01, 0, 0));
    EXPECT_EQ(jumping.read(0.001).position_m.x(), 0.01);  // without a follow time it goes straight there
}

// A script that knows its path gives the velocity; without it the step's finite difference stands.
TEST(VirtualDevice, AGivenVelocityReplacesTheFiniteDifference) {
    WorkspaceTransform workspace;
    workspace.scale = 2;
    VirtualDevice device(3.3, workspace);
    device.setMotion(Vec3::Zero(), Vec3(0.5, 0, 0), 1);
    const DeviceSample first = device.read(0);
    EXPECT_EQ(first.velocity_m_per_s, Vec3(1.0, 0, 0)) << "in scene units, from the first sample on";
    EXPECT_EQ(first.buttons, 1u);
    device.setMotion(Vec3(0.001, 0, 0), Vec3(0, -0.25, 0));
    EXPECT_EQ(device.read(0.001).velocity_m_per_s, Vec3(0, -0.5, 0)) << "not the 2 m/s the positions imply";
    device.setPosition(Vec3(0.002, 0, 0));
    EXPECT_NEAR(device.read(0.002).velocity_m_per_s.x(), 2.0, 1e-9) << "a plain position: the difference again";
}

TEST(HapticLoop, MaterialCommandsScaleTheModelLiveAndTheStableStepFollows) {
    HeartScene h;
    VirtualDevice device;
    device.setPosition(frontPoint(h) - Vec3(0, 0, 0.002));
    const double k0 = h.model.springs.stiffness[5], anchor0 = h.model.nodes.anchorStiffness[5],
                 m0 = h.model.nodes.mass[5];
    LoopConfig rk4;
    rk4.scheme = physics::Scheme::RungeKutta4;
    HapticLoop loop(h.organ, device, rk4);
    runSimulated(loop, 8);
    const double stable0 = loop.snapshots().readLatest().stableStep_s;
    ASSERT_GT(stable0, 0);
    ASSERT_TRUE(loop.commands().push({LoopCommand::Kind::ScalePositioningStiffness, 4.0}));
    ASSERT_TRUE(loop.commands().push({LoopCommand::Kind::ScaleStructuralStiffness, 2.0}));
    ASSERT_TRUE(loop.commands().push({LoopCommand::Kind::ScaleMass, 0.5}));
    ASSERT_TRUE(loop.commands().push({LoopCommand::Kind::ScaleMass, -1.0}));  // refused: not a scale
    runSimulated(loop, 8);
    EXPECT_DOUBLE_EQ(h.model.springs.stiffness[5], 2 * k0);
    EXPECT_DOUBLE_EQ(h.model.nodes.anchorStiffness[5], 4 * anchor0);
    EXPECT_DOUBLE_EQ(h.model.nodes.mass[5], 0.5 * m0);
    EXPECT_DOUBLE_EQ(h.model.nodes.inverseMass[5], 2 / m0);
    // Stiffer and lighter: the anchors' omega grows by sqrt(4 / 0.5), so the stable step shrinks (by
    // less than that factor: damping and the tool coupling, unchanged, also bound it).
    const double stable1 = loop.snapshots().readLatest().stableStep_s;
    EXPECT_LT(stable1, 0.75 * stable0);
    EXPECT_FALSE(loop.snapshots().readLatest().watchdogTripped);
}

// With the default Auto, the thesis's heart runs RK4 until the material is made so stiff that RK4 would
// need substeps; then the loop integrates implicitly, in one step per period.
TEST(HapticLoop, AutoTurnsImplicitWhenTheMaterialOutgrowsRK4) {
    HeartScene h;
    VirtualDevice device;
    device.setPosition(frontPoint(h) - Vec3(0, 0, 0.002));
    HapticLoop loop(h.organ, device);
    runSimulated(loop, 8);
    EXPECT_EQ(loop.scheme(), physics::Scheme::RungeKutta4);
    EXPECT_EQ(loop.snapshots().readLatest().scheme, physics::Scheme::RungeKutta4);
    ASSERT_TRUE(loop.commands().push({LoopCommand::Kind::ScaleStructuralStiffness, 10.0}));
    runSimulated(loop, 8);
    EXPECT_EQ(loop.scheme(), physics::Scheme::BackwardEuler);
    EXPECT_EQ(loop.substeps(), 1);
    EXPECT_EQ(loop.stats().solver.solves, 8);
    EXPECT_GT(loop.snapshots().readLatest().solverIterations, 0);
    EXPECT_FALSE(loop.snapshots().readLatest().watchdogTripped);
}

}  // namespace
}  // namespace hapticut::haptics

namespace hapticut::haptics {
namespace {

// A rough segmentation's faces tilt every way: stroked across a heart whose every vertex moved by up to
// 0.7 of a mean edge, the probe rests on folded slivers whose normals point sideways or back. Taken as the
// way the tool pushes, such a normal zeroed the force of a probe pressed 3-5 mm in, 93 of 1,198 steps along
// the stroke on the first of these hearts, a 1.5 N buzz in the hand. Pressed in, the hand feels the tissue
// push back in every step.
TEST(HapticLoop, AProbeStrokedAcrossARoughSegmentationIsPushedBackInEveryStepItIsPressedIn) {
    const auto stroke =
        readTrajectory(std::filesystem::path(HAPTICUT_SOURCE_DIR) / "assets/trajectories/stroke-front.csv");
    ASSERT_TRUE(stroke);
    const mesh::SurfaceMesh smooth = mesh::procedural::makeHeart({.triangles = 9714});
    for (unsigned seed : {1u, 2u, 3u}) {
        SCOPED_TRACE(testing::Message() << "seed " << seed);
        const mesh::SurfaceMesh rough = test::jitteredBy(smooth, 0.7 * test::meanEdgeOf(smooth), seed);
        cutting::CutModel organ(rough, physics::buildModel(rough, physics::Material{}));
        scene::HapticRunConfig config;
        config.loop.tipRadius_m = mesh::procedural::kProbeTipRadius_m;
        config.keepSteps = 3000;  // the whole stroke
        const auto run = scene::runHaptic(organ, *stroke, config);
        ASSERT_TRUE(run) << run.error().message;
        int pressed = 0, unfelt = 0;
        for (const StepOutput& step : run->keptSteps) {
            const HandStep& hand = step.hand();
            // Past the force's ramp, touching, the device a millimetre or more behind the proxy.
            if (step.t_s < 0.6 || !hand.contact || (hand.proxy_m - hand.device_m).norm() < 1e-3) continue;
            ++pressed;
            if (hand.force_N.norm() < 0.1) ++unfelt;
        }
        EXPECT_GT(pressed, 500) << "the stroke must press into the heart";
        EXPECT_EQ(unfelt, 0) << "of " << pressed << " steps pressed a millimetre or more in";
        EXPECT_FALSE(run->watchdogTripped);
    }
}

}  // namespace
}  // namespace hapticut::haptics
