// A tool tip's footprint: its load is the consistent load of a smooth pressure disk, it sinks into
// anchors as the continuum does (converging at second order) on meshes finer than the tip, a mesh coarser than the tip
// makes up the dent it cannot show, it slides smoothly, and the same press feels the same on coarse and fine hearts;
// a footprint too large for one step is built over several.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

#include "hapticut/collision/bvh.h"
#include "hapticut/haptics/contact_footprint.h"
#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/haptic_run.h"
#include "hapticut/scene/sample_trajectories.h"

namespace hapticut::haptics {
namespace {

namespace fs = std::filesystem;

constexpr double kFoundation_N_per_m3 = 8.8e6;  // the default material's anchors per m²

/// A flat sheet on anchors: a grid of `cells` x `cells` cells over 6 cm, optionally with every inner
/// node moved by up to `jitter` of a cell, with the default material's anchors per area.
struct Sheet {
    mesh::SurfaceMesh mesh;
    mesh::VertexFaces around;
    std::vector<double> anchor_N_per_m;

    Sheet(int cells, double jitter = 0) : mesh(mesh::procedural::makeGrid(cells, 0.06 / cells)) {
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(-jitter, jitter);
        const double h = 0.06 / cells;
        for (Vec3& p : mesh.positions)
            if (std::abs(p.x()) < 0.03 - h / 2 && std::abs(p.y()) < 0.03 - h / 2) {
                const double dy = u(rng) * h;  // y first, as the seed's sheet was made (random_vec.h)
                p += Vec3(u(rng) * h, dy, 0);
            }
        around = mesh::buildVertexFaces(mesh.faces, mesh.positions.size());
        physics::Material material;
        material.positioningStiffness_N_per_m3 = kFoundation_N_per_m3;
        anchor_N_per_m = physics::buildModel(mesh, material).nodes.anchorStiffness;
    }
    collision::SurfaceView view() const { return {mesh.positions, mesh.faces}; }

    /// The face under (x, y) and where on it.
    std::pair<std::uint32_t, Vec3> locate(double x, double y) const {
        const Vec3 p(x, y, 0);
        for (std::uint32_t f = 0; f < mesh.faces.size(); ++f) {
            const Vec3 a = mesh.positions[mesh.faces[f][0]], b = mesh.positions[mesh.faces[f][1]],
                       c = mesh.positions[mesh.faces[f][2]];
            const double area = (b - a).cross(c - a).z();
            const Vec3 bary((b - p).cross(c - p).z() / area, (c - p).cross(a - p).z() / area,
                            (a - p).cross(b - p).z() / area);
            if (bary.minCoeff() >= -1e-12) return {f, bary};
        }
        ADD_FAILURE() << "no face under " << x << ", " << y;
        return {0, Vec3(1, 0, 0)};
    }

    FootprintSpread press(ContactFootprint& footprint, double x, double y, double radius_m,
                          physics::PointSpring& tool) const {
        footprint.fitTo(mesh.positions.size(), mesh.faces.size());
        const auto [face, bary] = locate(x, y);
        return footprint.spread(view(), around, anchor_N_per_m, face, bary, radius_m, tool);
    }

    /// How far the held point sinks per newton on the anchors alone: node i takes w_i F and sinks
    /// w_i F / K_i, and the held point is the w-weighted mean of the nodes.
    double heldCompliance_m_per_N(const physics::PointSpring& tool) const {
        double c = 0;
        for (std::uint32_t k = 0; k < tool.count; ++k)
            c += tool.weights[k] * tool.weights[k] / anchor_N_per_m[tool.nodes[k]];
        return c;
    }
};

TEST(ContactFootprint, TheLoadSumsToOneAndHoldsTheSheetWhereTheTipTouches) {
    const Sheet sheet(60);  // 1 mm cells
    ContactFootprint footprint;
    physics::PointSpring tool;
    const double r = 0.007;
    ASSERT_TRUE(sheet.press(footprint, 0.0013, -0.0021, r, tool).complete);
    double sum = 0;
    for (std::uint32_t k = 0; k < tool.count; ++k) {
        sum += tool.weights[k];
        EXPECT_GE(tool.weights[k], 0);
        EXPECT_LT((sheet.mesh.positions[tool.nodes[k]] - Vec3(0.0013, -0.0021, 0)).norm(), r + 0.0015)
            << "only nodes whose faces reach under the tip";
    }
    EXPECT_NEAR(sum, 1, 1e-12);
    EXPECT_GT(tool.count, 100u) << "a 7 mm tip on 1 mm cells loads the nodes of some 150 mm²";
    EXPECT_TRUE(tool.spread);
    // The pressure is symmetric about the tip, so its load-weighted mean is the touched point.
    EXPECT_LT((tool.heldPoint(sheet.mesh.positions) - Vec3(0.0013, -0.0021, 0)).norm(), 0.01 * r);
}

TEST(ContactFootprint, OnAnchorsTheTipSinksAsTheContinuumDoesAtAnyMeshFinerThanTheTip) {
    // Pressure q ∝ (1 - s²)² on a foundation of k_p per m²: the load-weighted mean sinks
    // ∫q² / (k_p (∫q)²) = 9 / (5 π r² k_p) per newton, and the centre q(0) / (k_p ∫q) = 3 / (π r² k_p).
    const double r = 0.007;
    const double mean = 9 / (5 * std::numbers::pi * r * r * kFoundation_N_per_m3);
    const double centre = 3 / (std::numbers::pi * r * r * kFoundation_N_per_m3);
    ContactFootprint footprint;
    double lastError = 2.5;
    for (const int cells : {30, 60, 120}) {  // cells of 2, 1 and 0.5 mm
        SCOPED_TRACE(testing::Message() << cells << " cells");
        const Sheet sheet(cells);
        physics::PointSpring tool;
        const FootprintSpread s = sheet.press(footprint, 0.0007, 0.0011, r, tool);
        const double error = std::abs(sheet.heldCompliance_m_per_N(tool) / mean - 1);
        std::printf("%d cells: mean sink %.4g m/N (continuum %.4g), subgrid %.3g of the centre's\n", cells,
                    sheet.heldCompliance_m_per_N(tool), mean, s.subgridCompliance_m_per_N / centre);
        EXPECT_LT(error, cells == 30 ? 0.12 : 0.05);
        EXPECT_LT(error, lastError / 2.5) << "second order: about a quarter of the error at half the cell";
        lastError = error;
        // What the mesh cannot show at the centre shrinks as it resolves the tip.
        EXPECT_LT(s.subgridCompliance_m_per_N, (cells == 30 ? 0.3 : 0.15) * centre);
    }
    {
        const Sheet jittered(60, 0.35);  // a badly shaped mesh: nodes moved by up to 35% of a cell
        physics::PointSpring tool;
        jittered.press(footprint, 0.0007, 0.0011, r, tool);
        EXPECT_NEAR(jittered.heldCompliance_m_per_N(tool), mean, 0.06 * mean);
    }
    // The thesis's point contact sinks by the touched nodes' anchors: four times as deep on cells half
    // as wide, which is why a finer mesh used to feel softer.
    const Sheet coarse(30), fine(60);
    physics::PointSpring a, b;
    const auto [fa, ba] = coarse.locate(0.0007, 0.0011);
    const auto [fb, bb] = fine.locate(0.0007, 0.0011);
    a.touchTriangle(coarse.mesh.faces[fa], ba);
    b.touchTriangle(fine.mesh.faces[fb], bb);
    EXPECT_GT(fine.heldCompliance_m_per_N(b) / coarse.heldCompliance_m_per_N(a), 3.0);
}

TEST(ContactFootprint, ATipSmallerThanTheFacesLoadsTheTouchedCornersAndMakesUpTheDentTheyCannotShow) {
    const Sheet sheet(6);  // 1 cm cells
    ContactFootprint footprint;
    physics::PointSpring tool;
    const double r = 0.001;
    const FootprintSpread s = sheet.press(footprint, 0.0031, 0.0012, r, tool);
    const auto [face, bary] = sheet.locate(0.0031, 0.0012);
    ASSERT_EQ(tool.count, 3u) << "a 1 mm tip inside a 1 cm face";
    for (std::uint32_t k = 0; k < 3; ++k) {
        const int corner =
            static_cast<int>(std::find(sheet.mesh.faces[face].begin(), sheet.mesh.faces[face].end(), tool.nodes[k]) -
                             sheet.mesh.faces[face].begin());
        EXPECT_NEAR(tool.weights[k], bary[corner], 0.01) << "the barycentric point load";
    }
    // The whole continuum dent under the tip is missing from a mesh this coarse.
    const double centre = 3 / (std::numbers::pi * r * r * kFoundation_N_per_m3);
    EXPECT_NEAR(s.subgridCompliance_m_per_N, centre, 0.05 * centre);
}

TEST(ContactFootprint, SlidingTheTipShiftsItsLoadSmoothly) {
    const Sheet sheet(30, 0.3);  // 2 mm cells, jittered
    ContactFootprint footprint;
    std::vector<double> before(sheet.mesh.positions.size(), 0.0), now(before.size(), 0.0);
    double worst = 0;
    for (int i = 0; i <= 200; ++i) {  // 1 cm in 0.05 mm steps, across many faces and edges
        physics::PointSpring tool;
        sheet.press(footprint, -0.005 + 0.00005 * i, 0.0003, 0.007, tool);
        std::fill(now.begin(), now.end(), 0.0);
        for (std::uint32_t k = 0; k < tool.count; ++k) now[tool.nodes[k]] = tool.weights[k];
        if (i > 0) {
            double change = 0;
            for (std::size_t v = 0; v < now.size(); ++v) change += std::abs(now[v] - before[v]);
            worst = std::max(worst, change);
        }
        before.swap(now);
    }
    // A pressure of radius r moved by d changes the load by about 2 d / r in total; a load that jumped
    // from face to face would change by up to 2.
    EXPECT_LT(worst, 0.05);
}

// A footprint built a few faces at a time, as the haptic loop builds a large one over several steps,
// is the footprint built at once, to the bit; a new begin abandons a build under way.
TEST(ContactFootprint, BuiltInStepsItIsTheFootprintBuiltAtOnce) {
    const Sheet sheet(120, 0.3);  // 0.5 mm cells, jittered: a 7 mm tip covers about 1,200 faces
    ContactFootprint footprint;
    physics::PointSpring atOnce, inSteps;
    const FootprintSpread whole = sheet.press(footprint, 0.0013, -0.0021, 0.007, atOnce);
    const auto [face, bary] = sheet.locate(0.0013, -0.0021);
    const auto [elsewhere, elsewhereBary] = sheet.locate(-0.01, 0.004);
    footprint.begin(sheet.view(), elsewhere, elsewhereBary, 0.007);
    EXPECT_FALSE(footprint.advance(sheet.view(), sheet.around, 50));
    footprint.begin(sheet.view(), face, bary, 0.007);
    int calls = 1;
    while (!footprint.advance(sheet.view(), sheet.around, 50)) ++calls;
    const FootprintSpread stepped = footprint.finish(sheet.view(), sheet.around, sheet.anchor_N_per_m, inSteps);
    EXPECT_GT(calls, 20) << "many calls of 50 faces";
    ASSERT_EQ(inSteps.count, atOnce.count);
    for (std::uint32_t k = 0; k < atOnce.count; ++k) {
        ASSERT_EQ(inSteps.nodes[k], atOnce.nodes[k]);
        ASSERT_EQ(inSteps.weights[k], atOnce.weights[k]);
    }
    EXPECT_EQ(stepped.subgridCompliance_m_per_N, whole.subgridCompliance_m_per_N);
    EXPECT_EQ(stepped.complete, whole.complete);
    EXPECT_TRUE(inSteps.spread);
}

/// The hold force of the shipped press (6 mm below the surface) on a heart of `triangles`.
double pressForce_N(int triangles, double tipRadius_m) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({.triangles = triangles});
    collision::Bvh bvh;
    bvh.build({heart.positions, heart.faces});
    const Trajectory press = scene::pressTrajectory(heart, bvh);
    cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
    scene::HapticRunConfig config;
    config.loop.tipRadius_m = tipRadius_m;
    config.keepSteps = 1'000'000;
    const auto run = scene::runHaptic(organ, press, config);
    EXPECT_TRUE(run) << run.error().message;
    if (!run) return 0;
    double sum = 0;
    int n = 0;
    for (const StepOutput& s : run->keptSteps)
        if (s.t_s >= 1.3 && s.t_s <= 1.5) sum += s.hand().force_N.norm(), ++n;
    return sum / n;
}

TEST(ToolTip, TheSamePressFeelsTheSameOnCoarseAndFineHearts) {
    const double tip = mesh::procedural::kProbeTipRadius_m;
    std::vector<double> forces;
    for (const int triangles : {1619, 9714, 100'000}) forces.push_back(pressForce_N(triangles, tip));
    const auto [lo, hi] = std::minmax_element(forces.begin(), forces.end());
    EXPECT_LT(*hi / *lo, 1.10) << forces[0] << " N, " << forces[1] << " N, " << forces[2] << " N";
    EXPECT_GT(*lo, 0.8) << "a firm press";
    // With the thesis's point contact the finer heart feels a third as stiff.
    EXPECT_GT(pressForce_N(1619, 0) / pressForce_N(9714, 0), 2.0);
}

// A tip whose footprint walks more faces than a step may (kFootprintFacesPerStep: a 2 cm tip on the
// 100,000-triangle heart) gets it over several steps. Meanwhile a new touch loads the touched triangle,
// and a sliding tool keeps loading its last footprint: it never falls back to a point while it slides.
TEST(ToolTip, ALargeFootprintIsBuiltOverStepsWhileTheToolLoadsTheOneItHad) {
    const mesh::SurfaceMesh mesh = mesh::procedural::makeHeart({.triangles = 100'000});
    cutting::CutModel organ(mesh, physics::buildModel(mesh, physics::Material{}));
    const physics::PointSpring& tool = organ.model().tools[0];
    Vec3 front = mesh.positions[0];
    for (const Vec3& p : mesh.positions)
        if (std::abs(p.x()) < 0.01 && std::abs(p.y()) < 0.01 && p.z() > front.z()) front = p;
    Trajectory stroke;  // in from 2 mm off, then 2 cm across the front, pressed 4 mm
    auto add = [&](double t_s, double x, double z) {
        TrajectoryPoint p;
        p.t_s = t_s;
        p.sample.position_m = Vec3(front.x() + x, front.y(), front.z() + z);
        stroke.points.push_back(p);
    };
    add(0.0, -0.01, 0.002);
    add(0.1, -0.01, -0.004);
    add(0.5, 0.01, -0.004);
    ReplayDevice device(stroke);
    LoopConfig config;
    config.tipRadius_m = 0.02;
    HapticLoop loop(organ, device, config);
    std::vector<std::uint32_t> firstNodes;  // the loaded nodes at each step in contact: the first few
    long touchedAt = -1, triangleSteps = 0, rebuilds = 0, lostFootprint = 0, biggest = 0;
    runSimulated(loop, 500, [&](const StepOutput& s) {
        if (!s.hand().contact) return;
        const long step = std::lround(s.t_s * 1000);
        if (touchedAt < 0) touchedAt = step;
        if (!tool.spread) {
            ++triangleSteps;
            if (biggest > 0) ++lostFootprint;
            return;
        }
        biggest = std::max<long>(biggest, tool.count);
        const std::vector<std::uint32_t> now(tool.nodes.begin(), tool.nodes.begin() + 8);
        if (!firstNodes.empty() && now != firstNodes) ++rebuilds;
        firstNodes = now;
    });
    ASSERT_GE(touchedAt, 0) << "the stroke touches";
    EXPECT_GT(biggest, 1500) << "the tip loads thousands of nodes";
    EXPECT_GE(triangleSteps, 1) << "the first touch loads the touched triangle while the footprint is built";
    EXPECT_LE(triangleSteps, 8) << "and the footprint comes within a few steps";
    EXPECT_EQ(lostFootprint, 0) << "a sliding tool keeps its footprint until the next one is whole";
    EXPECT_GT(rebuilds, 10) << "the footprint is built again as the tool slides";
}

// In real time a build takes as many faces a step as fit in its budget at what a face has lately cost:
// under the scalpel on the 1,000,000 heart 2,048 faces took up to 340 µs of a 1 ms step. Simulated
// time takes kFootprintFacesPerStep every step (the tests above), so a run does not depend on the machine.
TEST(ToolTip, AFootprintsFacesAStepFitItsBudgetAtWhatAFaceCostLately) {
    EXPECT_EQ(footprintFacesPerStep(0), kFootprintFacesPerStep) << "nothing measured yet";
    EXPECT_EQ(footprintFacesPerStep(10), kFootprintFacesPerStep) << "faces in a warm cache";
    const double slow_ns = 2 * 1e3 * kFootprintBudget_us / static_cast<double>(kFootprintFacesPerStep);
    EXPECT_EQ(footprintFacesPerStep(slow_ns), kFootprintFacesPerStep / 2);
    EXPECT_LE(static_cast<double>(footprintFacesPerStep(slow_ns)) * slow_ns, 1e3 * kFootprintBudget_us);
    EXPECT_EQ(footprintFacesPerStep(1e9), kMinFootprintFaces) << "a build always goes on";
}

// A scalpel cuts every few steps. Its footprint outlives each cut as a load (cuts only add nodes) until
// the next one is whole: a build restarted at every cut never finished on a fine organ, the blade
// pressed on its touched triangle alone, and on the 1,000,000 heart nodes flew metres away.
TEST(ToolTip, WhileTheBladeCutsItsLoadStaysSpreadAndFollowsIt) {
    const mesh::SurfaceMesh mesh = mesh::procedural::makeHeart({.triangles = 100'000});
    cutting::CutModel organ(mesh, physics::buildModel(mesh, physics::Material{}));
    const physics::PointSpring& tool = organ.model().tools[0];
    auto stroke = readTrajectory(fs::path(HAPTICUT_SOURCE_DIR) / "assets/trajectories/cut-front.csv");
    ASSERT_TRUE(stroke) << stroke.error().toString();
    ReplayDevice device(*stroke);
    LoopConfig config;
    config.tipRadius_m = 0.02;  // a footprint of more faces than a step builds
    config.cutThreshold_N = mesh::procedural::kScalpelThreshold_N;
    HapticLoop loop(organ, device, config);
    long cutEvents = 0, pointLoadsWhileCutting = 0, footprintsWhileCutting = 0;
    std::vector<std::uint32_t> last;
    long changes = 0;
    double farthest_m = 0;
    runSimulated(loop, 1900, [&](const StepOutput& s) {
        cutEvents += s.cut;
        for (std::size_t i = 0; i < organ.model().nodes.size(); i += 97)
            farthest_m =
                std::max(farthest_m, (organ.model().nodes.position[i] - organ.model().nodes.restPosition[i]).norm());
        if (cutEvents == 0 || !s.hand().contact) return;
        if (!tool.spread) {
            ++pointLoadsWhileCutting;
            return;
        }
        ++footprintsWhileCutting;
        const std::vector<std::uint32_t> now(tool.nodes.begin(), tool.nodes.begin() + 8);
        changes += now != last;
        last = now;
    });
    ASSERT_GT(cutEvents, 10) << "the blade cuts";
    EXPECT_GT(footprintsWhileCutting, 300);
    EXPECT_EQ(pointLoadsWhileCutting, 0) << "the blade never presses on its touched triangle alone";
    EXPECT_GT(changes, 10) << "its footprint is built again as it cuts on";
    EXPECT_LT(farthest_m, 0.02) << "no node is flung from the organ";
}

}  // namespace
}  // namespace hapticut::haptics
