// Cutting you can feel: on a flat sheet the blade meets toughness x depth while it cuts, holds it when it
// stops and meets nothing back in its own cut; across the heart the hand feels the blade all the way
// through the cut, and the proxy never sinks into the organ, whose walls keep it closed.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "hapticut/geometry/random_vec.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/haptic_run.h"
#include "hapticut/scene/sample_trajectories.h"
#include "test_support.h"

namespace hapticut::haptics {
namespace {

Trajectory path(std::initializer_list<std::pair<double, Vec3>> points) {
    Trajectory t;
    for (const auto& [time, p] : points) {
        TrajectoryPoint point;
        point.t_s = time;
        point.sample.position_m = p;
        t.points.push_back(point);
    }
    return t;
}

/// A headless run with the shipped scalpel: its threshold and its blade's tip.
scene::HapticRunConfig scalpelRun() {
    scene::HapticRunConfig config;
    config.loop.cutThreshold_N = mesh::procedural::kScalpelThreshold_N;
    config.loop.tipRadius_m = mesh::procedural::kScalpelTipRadius_m;
    return config;
}

double mean(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0 : s / static_cast<double>(v.size());
}

TEST(CuttingFeel, OnAFlatSheetTheBladeMeetsToughnessTimesDepthHoldsItWhenStoppedAndNothingBackInItsCut) {
    // A 10 cm sheet of 5 mm cells facing +z; the blade goes 5 mm under it, cuts 4 cm along x at 2 cm/s,
    // stops, and draws back 5 mm along its own cut.
    const mesh::SurfaceMesh sheet = mesh::procedural::makeGrid(20, 0.005);
    cutting::CutModel organ(sheet, physics::buildModel(sheet, physics::Material{}));
    const double depth = 0.005, toughness = 200;
    const double y = 0.0013;  // between rows of vertices
    ReplayDevice device(path({{0.0, Vec3(-0.03, y, 0.01)},
                              {0.3, Vec3(-0.03, y, -depth)},
                              {0.5, Vec3(-0.03, y, -depth)},
                              {2.5, Vec3(0.01, y, -depth)},
                              {2.8, Vec3(0.01, y, -depth)},
                              {3.0, Vec3(0.005, y, -depth)}}));
    Hand hand{&device, 0.5};  // a sharp blade: the sheet gives way under half a newton
    hand.toughness_J_per_m2 = toughness;
    auto made = HapticLoop::create(organ, std::span<const Hand>(&hand, 1), LoopConfig{.rampTime_s = 0.05});
    ASSERT_TRUE(made) << made.error().message;
    HapticLoop& loop = **made;
    std::vector<double> cutting, stopped, back;
    runSimulated(loop, 3000, [&](const StepOutput& s) {
        const double along = -s.hand().force_N.x();  // against the blade's way
        if (s.t_s > 1.5 && s.t_s < 2.5) cutting.push_back(along);
        if (s.t_s > 2.55 && s.t_s < 2.8) stopped.push_back(along);
        // Drawn back past the 2.5 mm the tissue ahead was stretched by (J x depth / k at 400 N/m).
        if (s.t_s > 2.92 && s.t_s < 3.0) back.push_back(std::abs(s.hand().force_N.x()));
    });
    ASSERT_FALSE(loop.stats().watchdogTripped);
    EXPECT_GT(loop.stats().cutEvents, 5);
    EXPECT_GT(loop.cutter().stats().length_m, 0.02) << "the cut ran with the blade";
    const double expected = toughness * depth;  // 1 N
    EXPECT_NEAR(mean(cutting), expected, 0.1 * expected) << "while it cuts";
    for (double f : stopped) EXPECT_GT(f, 0.8 * expected) << "stopped in the tissue, the blade is still held";
    ASSERT_FALSE(back.empty());
    for (double f : back) EXPECT_LT(f, 0.1 * expected) << "back in its own cut nothing resists along it";
}

TEST(CuttingFeel, ATougherRegionOfTheSheetTakesThatMuchMoreForceToCut) {
    // The half of the sheet with x > 0 three times as tough (a scene's [[regions]] toughness_scale); the
    // blade cuts 7 cm along x at 1.75 cm/s, 5 mm deep, across the border.
    const mesh::SurfaceMesh sheet = mesh::procedural::makeGrid(20, 0.005);
    const physics::MaterialField tougher = [](const Vec3& p) {
        return physics::MaterialScale{1, 1, p.x() > 0 ? 3.0 : 1.0};
    };
    cutting::CutModel organ(sheet, physics::buildModel(sheet, physics::Material{}), tougher);
    const double depth = 0.005, toughness = 100, y = 0.0013;
    ReplayDevice device(path({{0.0, Vec3(-0.03, y, 0.01)},
                              {0.3, Vec3(-0.03, y, -depth)},
                              {0.5, Vec3(-0.03, y, -depth)},
                              {4.5, Vec3(0.04, y, -depth)}}));
    Hand hand{&device, 0.5};
    hand.toughness_J_per_m2 = toughness;
    auto made = HapticLoop::create(organ, std::span<const Hand>(&hand, 1), LoopConfig{.rampTime_s = 0.05});
    ASSERT_TRUE(made) << made.error().message;
    std::vector<double> soft, tough;
    runSimulated(**made, 4500, [&](const StepOutput& s) {
        const double blade_x = -0.03 + 0.07 * (s.t_s - 0.5) / 4.0;  // the crack tip trails it by force / k
        if (blade_x > -0.02 && blade_x < -0.005) soft.push_back(-s.hand().force_N.x());
        if (blade_x > 0.02 && blade_x < 0.035) tough.push_back(-s.hand().force_N.x());
    });
    EXPECT_GT((**made).cutter().stats().length_m, 0.05) << "the cut ran on through the tougher half";
    EXPECT_NEAR(mean(soft), toughness * depth, 0.1 * toughness * depth);
    EXPECT_NEAR(mean(tough), 3 * toughness * depth, 0.1 * 3 * toughness * depth);
}

/// A blade on the 10 cm sheet along a path of (time, position, the way its edge faces about +z in
/// degrees from +x): what it cut and the largest force against its motion along x.
struct SheetCut {
    double length_m = 0, maxAlongX_N = 0;
    Vec3 lastPoint = Vec3::Zero();
    long cutEvents = 0;
};
SheetCut cutSheet(std::initializer_list<std::tuple<double, Vec3, double>> points) {
    const mesh::SurfaceMesh sheet = mesh::procedural::makeGrid(20, 0.005);
    cutting::CutModel organ(sheet, physics::buildModel(sheet, physics::Material{}));
    Trajectory t;
    for (const auto& [time, p, edge_deg] : points) {
        TrajectoryPoint point;
        point.t_s = time;
        point.sample.position_m = p;
        point.sample.orientation = Eigen::AngleAxisd(edge_deg * 3.14159265358979 / 180, Vec3::UnitZ());
        point.sample.oriented = true;
        t.points.push_back(point);
    }
    ReplayDevice device(t);
    Hand hand{&device, 0.5};
    hand.toughness_J_per_m2 = 200;
    auto made = HapticLoop::create(organ, std::span<const Hand>(&hand, 1), LoopConfig{.rampTime_s = 0.05});
    EXPECT_TRUE(made);
    SheetCut r;
    if (!made) return r;
    HapticLoop& loop = **made;
    runSimulated(loop, static_cast<long>(1000 * t.points.back().t_s), [&](const StepOutput& s) {
        r.maxAlongX_N = std::max(r.maxAlongX_N, std::abs(s.hand().force_N.x()));
        if (loop.cutter().cutting() && !loop.cutter().points().empty())
            r.lastPoint = organ.mesh().positions[loop.cutter().points().back()];
    });
    r.length_m = loop.cutter().stats().length_m;
    r.cutEvents = loop.stats().cutEvents;
    return r;
}

TEST(CuttingFeel, TheBladeCutsTheWayItsEdgeFacesAndDraggedSidewaysItCutsNothing) {
    const double y = 0.0013, z = -0.005;
    // Edge forward along the stroke: it cuts, as a blade without orientation does.
    const SheetCut forward = cutSheet({{0.0, Vec3(-0.03, y, 0.01), 0},
                                       {0.3, Vec3(-0.03, y, z), 0},
                                       {0.5, Vec3(-0.03, y, z), 0},
                                       {1.5, Vec3(-0.01, y, z), 0}});
    EXPECT_GT(forward.length_m, 0.01);
    // The same stroke with the edge turned across it (facing +y): the flat of the blade is dragged
    // through the tissue, which pushes back hard, and nothing is cut beyond where it went in.
    const SheetCut sideways = cutSheet({{0.0, Vec3(-0.03, y, 0.01), 90},
                                        {0.3, Vec3(-0.03, y, z), 90},
                                        {0.5, Vec3(-0.03, y, z), 90},
                                        {1.5, Vec3(-0.01, y, z), 90}});
    EXPECT_LT(sideways.length_m, 0.004) << "dragged sideways, a blade does not cut";
    EXPECT_GT(sideways.maxAlongX_N, 2.0) << "and the tissue resists the drag";
    // Turning the blade turns the cut: 1.5 cm along +x, then the edge turned to +y and the blade with it.
    const SheetCut turned = cutSheet({{0.0, Vec3(-0.03, y, 0.01), 0},
                                      {0.3, Vec3(-0.03, y, z), 0},
                                      {0.5, Vec3(-0.03, y, z), 0},
                                      {1.25, Vec3(-0.015, y, z), 0},
                                      {1.35, Vec3(-0.015, y, z), 90},
                                      {2.35, Vec3(-0.015, y + 0.02, z), 90}});
    EXPECT_GT(turned.lastPoint.y(), y + 0.01) << "the cut followed the turned edge";
    EXPECT_NEAR(turned.lastPoint.x(), -0.015, 0.006);
}

// The incision exercise's 3 cm stroke on a fine heart (1 mm edges). The blade's target comes back near
// the lips the cut has just opened, within snapping distance of the edges from a lip down to the cut's
// own floor: the cut used to snap onto one, join itself there and end, and cut 12.6 mm in all. It now
// cuts the stroke's length. (Release builds only: 2,200 implicit steps of a 50,000-triangle organ.)
TEST(CuttingFeel, AnIncisionOnTheFiftyThousandTriangleHeartCutsItsWholeLength) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({.triangles = 50'000});
    collision::Bvh bvh;
    bvh.build({heart.positions, heart.faces});
    const Trajectory stroke = scene::incisionStroke(heart, bvh, -0.01, -0.015, 0.015, 0.01);
    cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
    scene::HapticRunConfig config = scalpelRun();
    const auto run = scene::runHaptic(organ, stroke, config);
    ASSERT_TRUE(run) << run.error().message;
    EXPECT_EQ(run->cut.joins, 0);
    EXPECT_GT(run->cut.length_m, 0.028) << "the stroke is 30 mm along the surface";
    EXPECT_LE(run->cut.cuts, 2);
    EXPECT_TRUE(run->invariantProblems.empty()) << run->invariantProblems.front();
}

TEST(CuttingFeel, AcrossTheHeartTheHandFeelsTheBladeThroughoutTheCutAndTheProxyStaysOutside) {
    // With the thesis's point contact and with the scalpel's tip as users get it. Under a sanitizer the
    // 1,619 heart only: the 9,714 one runs the same code, and took 40 of its 44 s under ASan.
    std::vector<std::pair<int, double>> cases{{1619, 0.0}, {1619, mesh::procedural::kScalpelTipRadius_m}};
#ifndef HAPTICUT_SANITIZED
    cases.insert(cases.end(), {{9714, 0.0}, {9714, mesh::procedural::kScalpelTipRadius_m}});
#endif
    for (const auto& [triangles, tip_m] : cases) {
        SCOPED_TRACE(testing::Message() << triangles << " triangles, tip " << tip_m << " m");
        const auto trajectory =
            readTrajectory(std::filesystem::path(HAPTICUT_SOURCE_DIR) / "assets/trajectories/cut-front.csv");
        ASSERT_TRUE(trajectory);
        const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({.triangles = triangles});
        cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
        scene::HapticRunConfig config;
        config.loop.cutThreshold_N = mesh::procedural::kScalpelThreshold_N;
        config.loop.tipRadius_m = tip_m;
        config.keepSteps = 1'000'000;
        const auto run = scene::runHaptic(organ, *trajectory, config);
        ASSERT_TRUE(run) << run.error().message;
        const scene::HapticRunResult& r = *run;
        long first = -1, last = -1;
        for (std::size_t i = 0; i < r.keptSteps.size(); ++i)
            if (r.keptSteps[i].cut) {
                if (first < 0) first = static_cast<long>(i);
                last = static_cast<long>(i);
            }
        ASSERT_GE(first, 0) << "the scalpel cut";
        long felt = 0;
        for (long i = first; i <= last; ++i)
            felt += r.keptSteps[static_cast<std::size_t>(i)].hand().force_N.norm() >= 0.3;
        EXPECT_GE(static_cast<double>(felt), 0.95 * static_cast<double>(last - first + 1))
            << "from the first cut event to the last, " << felt << " of " << last - first + 1 << " steps";
        EXPECT_GT(r.cut.length_m, 0.02);
        // The walls keep the heart closed, so the proxy's penetration is measured in every step.
        EXPECT_EQ(r.penetrationMeasuredSteps, r.steps);
        EXPECT_LT(r.maxProxyPenetration_m, 1e-4);
        EXPECT_TRUE(r.invariantProblems.empty()) << r.invariantProblems.front();
    }
}

/// How far along x, the scalpel stroke's way, the vertices a run added reach: the cut's span.
double spanAlongX(const cutting::CutModel& organ, std::size_t verticesBefore) {
    double lo = 1e300, hi = -1e300;
    for (std::size_t v = verticesBefore; v < organ.mesh().positions.size(); ++v)
        lo = std::min(lo, organ.mesh().positions[v].x()), hi = std::max(hi, organ.mesh().positions[v].x());
    return hi > lo ? hi - lo : 0.0;
}

struct StrokeCut {
    long cuts = 0;
    double length_m = 0, span_m = 0;
    double penetration_m = 0;  // the proxy's deepest inside the surface in any step (ray parity)
};

/// The scalpel's stroke through the loop across a fresh copy of `heart`, which stays closed and whole.
StrokeCut strokeCut(const mesh::SurfaceMesh& heart, const Trajectory& stroke) {
    cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
    const auto run = scene::runHaptic(organ, stroke, scalpelRun());
    EXPECT_TRUE(run) << run.error().message;
    if (!run) return {};
    EXPECT_TRUE(run->invariantProblems.empty()) << run->invariantProblems.front();
    EXPECT_EQ(run->penetrationMeasuredSteps, run->steps) << "the organ stays closed";
    return {run->cut.cuts, run->cut.length_m, spanAlongX(organ, heart.positions.size()), run->maxProxyPenetration_m};
}

// An organ as a segmentation gives it: every vertex moved at random by up to a third of the mean edge,
// which leaves slivers, faces tilted tens of degrees and fans that fold. The scalpel's stroke cuts across
// it in one cut, most of the way it cuts across the smooth heart. Seen in space, the way from a cut point
// to the blade crossed no edge of such a fan, and the cut stayed where it was while the blade went on:
// 9.6 mm of cut on one of these hearts, two cuts on another.
TEST(CuttingFeel, AScalpelStrokeOverAJitteredHeartCutsAsFarAsOverTheSmoothOne) {
    const auto trajectory =
        readTrajectory(std::filesystem::path(HAPTICUT_SOURCE_DIR) / "assets/trajectories/cut-front.csv");
    ASSERT_TRUE(trajectory);
    const mesh::SurfaceMesh smooth = mesh::procedural::makeHeart({.triangles = 30000});
    const double smoothLength = strokeCut(smooth, *trajectory).length_m;
    const double meanEdge = test::meanEdgeOf(smooth);
#ifdef HAPTICUT_SANITIZED
    const std::vector<unsigned> seeds{6};  // the one that cut least; the code is the same for all
#else
    const std::vector<unsigned> seeds{1, 2, 3, 4, 5, 6};
#endif
    for (unsigned seed : seeds) {
        SCOPED_TRACE(testing::Message() << "seed " << seed);
        const mesh::SurfaceMesh jittered = test::jitteredBy(smooth, meanEdge / 3, seed);
        const StrokeCut cut = strokeCut(jittered, *trajectory);
        EXPECT_EQ(cut.cuts, 1);
        // 1.04 at the least. Seed 6 cut 0.66 before a cut turned round by a crack that first ran up the
        // slope could step back along an edge out of a folded fan (ProgressiveCutter::crossToward).
        EXPECT_GT(cut.length_m, 0.9 * smoothLength) << "smooth: " << smoothLength << " m";
        EXPECT_LT(cut.penetration_m, 5e-5) << "the proxy stays outside, but for the offset across a fresh cut's lips";
    }
}

// Near the stroke's end on this jittered heart the cut strays a millimetre off the blade's line and its
// lips are pressed through each other. The proxy rested on the far lip, in the near tissue; the blade
// lifted out to its side, the proxy followed the device 1.8 mm into the tissue, where the faces round
// its nearest point (the far lip's) said it was outside. It is held on the lips now. (A fresh cut's lips
// lie on each other: a proxy resting on one is its offset, 10 µm, inside the other's tissue.) The stroke is
// chaotic: written 1/3, the jitter's last bits differ and this seed's lips do not cross; seed 6 then went
// 0.61 mm in. Proxy.PulledOffLipsPressedThroughEachOther... is the same case built not to hang on such bits.
TEST(CuttingFeel, ABladeLiftedOutBesideLipsPressedThroughEachOtherLeavesTheProxyOutside) {
    const auto trajectory =
        readTrajectory(std::filesystem::path(HAPTICUT_SOURCE_DIR) / "assets/trajectories/cut-front.csv");
    ASSERT_TRUE(trajectory);
    const mesh::SurfaceMesh smooth = mesh::procedural::makeHeart({.triangles = 9714});
    const StrokeCut cut = strokeCut(test::jitteredBy(smooth, test::meanEdgeOf(smooth) * 0.3333, 3), *trajectory);
    EXPECT_EQ(cut.cuts, 1);
    EXPECT_LT(cut.penetration_m, 5e-5);
}

// Jittered by half the mean edge, as a noisy segmentation is: many vertices stick out past all their
// neighbours with their faces turned over, so that no edge of their fan leads toward the blade, or
// only across the lips the cut has just opened. The cut steps along an edge to the neighbour nearest
// the blade and goes on. It used to stay at such a vertex while the blade pressed on at the force
// clamp: 12 and 29 mm of the smooth heart's 47 on two of these hearts (seeds 4 and 5), and 3.9 mm of 50
// on a jittered 960,796-triangle liver.
TEST(CuttingFeel, AScalpelStrokeOverAHeartJitteredByHalfAnEdgeCutsAcrossIt) {
    const auto trajectory =
        readTrajectory(std::filesystem::path(HAPTICUT_SOURCE_DIR) / "assets/trajectories/cut-front.csv");
    ASSERT_TRUE(trajectory);
    const mesh::SurfaceMesh smooth = mesh::procedural::makeHeart({.triangles = 9714});
    const double smoothSpan = strokeCut(smooth, *trajectory).span_m;
    EXPECT_GT(smoothSpan, 0.04);
    const double meanEdge = test::meanEdgeOf(smooth);
#ifdef HAPTICUT_SANITIZED
    const std::vector<unsigned> seeds{4};  // the one that cut least before; the code is the same for all
#else
    const std::vector<unsigned> seeds{1, 2, 3, 4, 5, 6};
#endif
    for (unsigned seed : seeds) {
        SCOPED_TRACE(testing::Message() << "seed " << seed);
        const mesh::SurfaceMesh jittered = test::jitteredBy(smooth, meanEdge / 2, seed);
        const StrokeCut cut = strokeCut(jittered, *trajectory);
        EXPECT_EQ(cut.cuts, 1);
        // 0.86 at the least (seed 1).
        EXPECT_GT(cut.span_m, 0.8 * smoothSpan) << "smooth: " << smoothSpan << " m";
        EXPECT_LT(cut.penetration_m, 5e-5);
    }
}

/// Top to bottom across the front at x, from 5 mm above the incision's line to 25 mm below, a centimetre
/// deep, as the exercise's incision stroke is made.
Trajectory strokeAcross(const mesh::SurfaceMesh& heart, const collision::Bvh& bvh, double x) {
    Trajectory across;
    auto at = [&](double t, double y, double offset, unsigned buttons) {
        TrajectoryPoint p;
        p.t_s = t;
        p.sample.position_m = scene::frontPoint(heart, bvh, x, y) + offset * scene::frontNormal(heart, bvh, x, y);
        p.sample.buttons = buttons;
        across.points.push_back(p);
    };
    at(0, 0.005, 0.03, 0);
    at(0.6, 0.005, 0.003, 1);
    for (int i = 0; i <= 30; ++i) at(0.9 + i * 0.033, 0.005 - i * 0.001, -0.01, 1);
    at(2.3, -0.025, 0.03, 0);
    return across;
}

// A stroke across an earlier incision on the 9,714 heart: the cut goes through the first wound (down its
// near wall to the floor, up the far wall) in one cut, the hand feels the blade all the way across, and
// the heart stays closed with the proxy outside.
TEST(CuttingFeel, AStrokeAcrossAnEarlierIncisionCutsThroughItAndTheHandFeelsTheBladeAllTheWay) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({.triangles = 9714});
    collision::Bvh bvh;
    bvh.build({heart.positions, heart.faces});
    cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
    scene::HapticRunConfig config = scalpelRun();
    const auto first = scene::runHaptic(organ, scene::incisionStroke(heart, bvh, -0.01, -0.015, 0.015, 0.01), config);
    ASSERT_TRUE(first) << first.error().message;
    ASSERT_GT(first->cut.length_m, 0.02);
    std::vector<bool> oldFloor(organ.mesh().positions.size());
    for (std::uint32_t v = 0; v < oldFloor.size(); ++v) oldFloor[v] = organ.isFloor(v);
    const std::size_t oldFaces = organ.mesh().faces.size();

    config.keepSteps = 1'000'000;
    const auto run = scene::runHaptic(organ, strokeAcross(heart, bvh, 0), config);
    ASSERT_TRUE(run) << run.error().message;
    const scene::HapticRunResult& r = *run;
    EXPECT_EQ(r.cut.woundsCrossed, 1);
    EXPECT_EQ(r.cut.joins, 0);
    EXPECT_GT(r.cut.length_m, 0.025) << "one cut across the whole stroke";
    int newWallsAtOldFloor = 0;
    for (std::size_t f = oldFaces; f < organ.mesh().faces.size(); ++f) {
        const mesh::Face& face = organ.mesh().faces[f];
        newWallsAtOldFloor +=
            organ.isWall(static_cast<std::uint32_t>(f)) &&
            std::any_of(face.begin(), face.end(), [&](std::uint32_t v) { return v < oldFloor.size() && oldFloor[v]; });
    }
    EXPECT_GE(newWallsAtOldFloor, 4) << "the first wound's walls cut down to its floor on both sides";
    long firstCut = -1, lastCut = -1;
    for (std::size_t i = 0; i < r.keptSteps.size(); ++i)
        if (r.keptSteps[i].cut) {
            if (firstCut < 0) firstCut = static_cast<long>(i);
            lastCut = static_cast<long>(i);
        }
    ASSERT_GE(firstCut, 0);
    long felt = 0;
    for (long i = firstCut; i <= lastCut; ++i)
        felt += r.keptSteps[static_cast<std::size_t>(i)].hand().force_N.norm() >= 0.3;
    EXPECT_GE(static_cast<double>(felt), 0.95 * static_cast<double>(lastCut - firstCut + 1))
        << felt << " of " << lastCut - firstCut + 1 << " steps";
    EXPECT_EQ(r.penetrationMeasuredSteps, r.steps);
    EXPECT_LT(r.maxProxyPenetration_m, 1e-4);
    EXPECT_TRUE(r.invariantProblems.empty()) << r.invariantProblems.front();
}

// The stroke `hapticut bench --cutting` times: the scalpel pressed 12 mm in along the view, at a slant to
// the heart's sloping front, and drawn 4 cm across it, with the tissue held still. The crack once started
// at the proxy: the slant alone stretched it sideways past the blade's hold, it ran off downhill, took
// that as its way, and the stroke forward never cut again (1-2 cut events on the 1,619 and 9,714 hearts).
TEST(CuttingFeel, AStrokePressedInAtASlantCutsAlongItsWay) {
    for (const int triangles : {1619, 9714}) {
        SCOPED_TRACE(triangles);
        const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({.triangles = triangles});
        collision::Bvh bvh;
        bvh.build({heart.positions, heart.faces});
        cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
        const Trajectory path = scene::strokeTrajectory(heart, bvh, 0.012);
        ReplayDevice device(path);
        LoopConfig config;
        config.cutThreshold_N = mesh::procedural::kScalpelThreshold_N;
        config.tipRadius_m = mesh::procedural::kScalpelTipRadius_m;
        HapticLoop loop(organ, device, config);
        loop.commands().push({LoopCommand::Kind::Pause, 0});
        runSimulated(loop, std::lround(path.duration_s() * config.rate_hz) + 1);
        EXPECT_GT(loop.stats().cutEvents, 10);
        EXPECT_GT(loop.cutter().stats().length_m, 0.025) << "most of the 4 cm stroke";
    }
}

/// The 9,714 heart with every vertex moved at random by up to 0.4 of a mean edge along each axis.
mesh::SurfaceMesh heartOfSlivers(unsigned seed) {
    mesh::SurfaceMesh heart = mesh::procedural::makeHeart({.triangles = 9714});
    const double jitter = mesh::meanEdgeLength(heart) * 0.4;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-jitter, jitter);
    for (Vec3& p : heart.positions) p += randomVec3(u, rng);
    mesh::computeFaceNormals(heart);
    return heart;
}

// The same two strokes on a heart of slivers, as a segmentation gives them: every vertex of the 9,714 heart
// moved by up to 0.4 of a mean edge along each axis (smallest angle 0.38 degrees, shortest edge 0.21 mm
// against a mean of 2.5). Each stroke cuts in one piece and the second goes through the first wound. On
// such a mesh the way on used to snap back onto the cut's own lip, or cross it first where the cut bent,
// and the cut ended or stalled a few millimetres in; single faces tilted tens of degrees turned the
// crack's plane until the blade seemed to pull it backwards. Before, the second stroke here cut 5 mm and
// did not cross the first wound.
TEST(CuttingFeel, OnAHeartOfSliversEachStrokeCutsInOnePieceAndTheSecondCrossesTheFirst) {
    const mesh::SurfaceMesh heart = heartOfSlivers(7);
    collision::Bvh bvh;
    bvh.build({heart.positions, heart.faces});
    cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
    scene::HapticRunConfig config = scalpelRun();
    const auto first = scene::runHaptic(organ, scene::incisionStroke(heart, bvh, -0.01, -0.015, 0.015, 0.01), config);
    ASSERT_TRUE(first) << first.error().message;
    EXPECT_EQ(first->cut.cuts, 1);
    EXPECT_GT(first->cut.length_m, 0.028) << "the stroke's 30 mm, along the mesh's edges";
    const auto second = scene::runHaptic(organ, strokeAcross(heart, bvh, 0), config);
    ASSERT_TRUE(second) << second.error().message;
    EXPECT_EQ(second->cut.cuts, 1);
    EXPECT_GE(second->cut.woundsCrossed, 1);
    EXPECT_EQ(second->cut.joins, 0);
    EXPECT_GT(second->cut.length_m, 0.028);
    EXPECT_EQ(second->penetrationMeasuredSteps, second->steps);
    EXPECT_LT(second->maxProxyPenetration_m, 1e-4);
    EXPECT_TRUE(second->invariantProblems.empty()) << second->invariantProblems.front();
}

// The same crossing stroke on more hearts of slivers, whose first wound, cut along their edges, zigzags.
// The second cut goes through it once and on down to the stroke's end (the stroke reaches 25 mm below the
// heart's front centre; the blade comes up over the last millimetres). Before, on five of these six (of
// sixteen hearts tried) it stopped 10-13 mm down, just past the wound: its far lip ran back into the way,
// the cut crossed back over it beside where it had entered and found no way on there. On the sixth
// (seed 9) it stopped 2.5 mm in: the crack first ran up the slope, turned round, and the way back
// crossed only the lips it had just opened.
TEST(CuttingFeel, OnHeartsOfSliversAStrokeAcrossAZigzagWoundCrossesItOnceAndCutsOnToItsEnd) {
#ifdef HAPTICUT_SANITIZED
    const std::vector<unsigned> seeds{9, 10};  // the two ways it stopped; the code is the same for all
#else
    const std::vector<unsigned> seeds{4, 8, 9, 10, 11, 14};
#endif
    for (const unsigned seed : seeds) {
        SCOPED_TRACE(testing::Message() << "seed " << seed);
        const mesh::SurfaceMesh heart = heartOfSlivers(seed);
        collision::Bvh bvh;
        bvh.build({heart.positions, heart.faces});
        cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
        const scene::HapticRunConfig config = scalpelRun();
        const auto first =
            scene::runHaptic(organ, scene::incisionStroke(heart, bvh, -0.01, -0.015, 0.015, 0.01), config);
        ASSERT_TRUE(first) << first.error().message;
        ASSERT_EQ(first->cut.cuts, 1);
        const std::size_t verticesBefore = organ.mesh().positions.size();
        const auto second = scene::runHaptic(organ, strokeAcross(heart, bvh, 0), config);
        ASSERT_TRUE(second) << second.error().message;
        EXPECT_EQ(second->cut.cuts, 1);
        EXPECT_EQ(second->cut.woundsCrossed, 1);
        EXPECT_EQ(second->cut.joins, 0);
        double lowest = 1;  // m: how far down the front the second cut's points reach
        for (std::size_t v = verticesBefore; v < organ.mesh().positions.size(); ++v)
            if (!organ.isFloor(static_cast<std::uint32_t>(v))) lowest = std::min(lowest, organ.mesh().positions[v].y());
        EXPECT_LT(lowest, -0.018) << "the cut reaches within 7 mm of the stroke's end";
        EXPECT_GT(second->cut.length_m, 0.025);
        EXPECT_TRUE(second->invariantProblems.empty()) << second->invariantProblems.front();
        EXPECT_EQ(second->penetrationMeasuredSteps, second->steps) << "the organ stays closed";
    }
}

// A device that jumps a metre between two samples (a glitch of the driver, a tracker losing its
// marker), while the scalpel cuts: out into the room, back deep into the organ from above, and through
// the organ to its back in one step. The hand is never pushed harder than the device's maximum nor
// faster than the force rate allows, the proxy stays outside, nothing is non-finite, and the organ stays
// sound.
TEST(Faults, AScalpelWhoseDeviceJumpsAMetreBetweenSamplesStaysSafe) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
    const double z = 0.0302;  // the front near y = -1 cm
    const Trajectory jumps = path({{0.0, {-0.02, -0.01, 0.06}},
                                   {0.6, {-0.02, -0.01, z + 0.003}},
                                   {0.9, {-0.02, -0.01, z - 0.01}},
                                   {1.2, {0.0, -0.01, z - 0.01}},
                                   {1.201, {1.0, 1.0, 1.0}},  // a metre away in a millisecond
                                   {1.4, {1.0, 1.0, 1.0}},
                                   {1.401, {0.005, -0.01, z - 0.015}},  // and back, deep in the organ
                                   {1.6, {0.01, -0.01, z - 0.015}},
                                   {1.601, {0.01, -0.01, -0.2}},  // through the organ to behind it
                                   {1.8, {0.01, -0.01, -0.2}},
                                   {1.801, {0.01, -0.01, 0.06}},
                                   {2.0, {0.01, -0.01, 0.06}}});
    scene::HapticRunConfig config;
    config.loop.cutThreshold_N = mesh::procedural::kScalpelThreshold_N;
    config.keepSteps = 1'000'000;
    const auto run = scene::runHaptic(organ, jumps, config);
    ASSERT_TRUE(run) << run.error().message;
    const scene::HapticRunResult& r = *run;
    EXPECT_GT(r.cut.cuts, 0) << "the scalpel was cutting when the device jumped";
    EXPECT_FALSE(r.watchdogTripped);
    EXPECT_EQ(r.nonFiniteEvents, 0);
    EXPECT_LE(r.maxForce_N, kDefaultMaxForce_N + 1e-9);
    EXPECT_EQ(r.penetrationMeasuredSteps, r.steps);
    EXPECT_LT(r.maxProxyPenetration_m, 1e-4);
    EXPECT_TRUE(r.invariantProblems.empty()) << r.invariantProblems.front();
    double largestRise_N = 0;
    for (std::size_t i = 1; i < r.keptSteps.size(); ++i)
        largestRise_N =
            std::max(largestRise_N, r.keptSteps[i].hand().force_N.norm() - r.keptSteps[i - 1].hand().force_N.norm());
    EXPECT_LE(largestRise_N, kDefaultMaxForceRate_N_per_s * 1e-3 + 1e-9) << "no jolt: 1.5 N a millisecond at most";
    EXPECT_TRUE(physics::allFinite(organ.model()));
}

}  // namespace
}  // namespace hapticut::haptics
