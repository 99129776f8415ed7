// Tissue that is not uniform: regions read from a scene, the material scaled where they are, a lump felt
// through the surface, and cuts through a lump that keep its stiffness.
#include <gtest/gtest.h>

#include <fstream>

#include "hapticut/collision/bvh.h"
#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/scene/haptic_run.h"
#include "hapticut/scene/sample_trajectories.h"
#include "hapticut/scene/scene.h"
#include "hapticut/scene/tissue_regions.h"
#include "test_support.h"

namespace hapticut::scene {
namespace {

using test::expectError;

class TissueRegions : public ::testing::Test {
protected:
    Result<Scene, Error> load(const std::string& text) {
        std::ofstream(dir / "scene.toml") << text;
        SceneRequest request;
        request.file = dir / "scene.toml";
        return loadScene(request);
    }
    test::ScratchDir dir;
};

/// Where the heart's front is at `where`: on its surface, by a ray from in front.
Vec3 frontOf(const Scene& scene, const Vec2& where) {
    collision::Bvh bvh;
    bvh.build({scene.source.mesh.positions, scene.source.mesh.faces});
    return frontPoint(scene.source.mesh, bvh, where.x(), where.y());
}

/// The probe's hold force in the shipped 6 mm press at `where`.
double pressForce_N(const Scene& scene, const Vec2& where) {
    collision::Bvh bvh;
    bvh.build({scene.source.mesh.positions, scene.source.mesh.faces});
    cutting::CutModel organ = scene.makeOrgan();
    HapticRunConfig config;
    config.loop = scene.loopConfig();
    config.loop.tipRadius_m = mesh::procedural::kProbeTipRadius_m;
    config.keepSteps = 1'000'000;
    const auto run = runHaptic(organ, pressTrajectory(scene.source.mesh, bvh, where), config);
    EXPECT_TRUE(run) << run.error().message;
    if (!run) return 0;
    double sum = 0;
    int n = 0;
    for (const haptics::StepOutput& s : run->keptSteps)
        if (s.t_s >= 1.3 && s.t_s <= 1.5) sum += s.hand().force_N.norm(), ++n;
    return sum / n;
}

TEST_F(TissueRegions, APressAboveAFiveTimesStifferLumpFeelsItAndTheSamePressAwayDoesNot) {
    const Vec2 above = kHeartFront, away(0.025, -0.01);
    const auto plain = load("[model]\nsource = \"heart\"\n");
    ASSERT_TRUE(plain) << plain.error().toString();
    const Vec3 surface = frontOf(*plain, above);
    const Vec3 centre = surface - Vec3(0, 0, 0.003);  // 3 mm under the front, 1 cm across
    const auto lumpy = load("[model]\nsource = \"heart\"\n[[regions]]\nshape = \"sphere\"\ncenter_m = [" +
                            std::to_string(centre.x()) + ", " + std::to_string(centre.y()) + ", " +
                            std::to_string(centre.z()) + "]\nradius_m = 0.01\nstiffness_scale = 5.0\nhidden = true\n");
    ASSERT_TRUE(lumpy) << lumpy.error().toString();
    ASSERT_EQ(lumpy->settings.regions.size(), 1u);
    EXPECT_TRUE(lumpy->settings.regions[0].hidden);

    const double onLump = pressForce_N(*lumpy, above), offLump = pressForce_N(*lumpy, away);
    const double plainAbove = pressForce_N(*plain, above), plainAway = pressForce_N(*plain, away);
    EXPECT_GT(onLump, 1.5 * offLump) << onLump << " N above the lump, " << offLump << " N away";
    // The places differ a little by themselves (the front is curved); the lump is most of it.
    EXPECT_GT(onLump, 1.3 * plainAbove) << onLump << " N above the lump, " << plainAbove << " N there without it";
    EXPECT_NEAR(offLump, plainAway, 0.02 * plainAway) << "away from the lump the tissue is as it was";
}

TEST_F(TissueRegions, SpringsAndAnchorsAreScaledWhereTheRegionIsAndCutsThroughItKeepItsScale) {
    // A box over the part of a flat 4 cm sheet (2 mm cells) with x below -1.5 mm: no node and no spring's
    // midpoint on its side.
    const mesh::SurfaceMesh sheet = mesh::procedural::makeGrid(20, 0.002);
    ASSERT_FALSE(mesh::io::saveMesh(dir / "sheet.obj", sheet, {}).has_value());
    const auto uniform = load("[model]\nsource = \"sheet.obj\"\n");
    const auto half = load(
        "[model]\nsource = \"sheet.obj\"\n[[regions]]\nshape = \"box\"\ncenter_m = [-0.5015, 0.0, 0.0]\n"
        "size_m = [1.0, 1.0, 1.0]\nstiffness_scale = 5.0\ndamping_scale = 2.0\n");
    ASSERT_TRUE(uniform) << uniform.error().toString();
    ASSERT_TRUE(half) << half.error().toString();
    const physics::MassSpringModel a = uniform->buildModel(), b = half->buildModel();
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        const bool inside = a.nodes.restPosition[i].x() < -0.0015;
        EXPECT_DOUBLE_EQ(b.nodes.anchorStiffness[i], (inside ? 5.0 : 1.0) * a.nodes.anchorStiffness[i]);
        EXPECT_DOUBLE_EQ(b.nodes.anchorDamping[i], (inside ? 2.0 : 1.0) * a.nodes.anchorDamping[i]);
    }
    for (std::size_t k = 0; k < a.springs.size(); ++k) {
        const double mid = 0.5 * (a.nodes.restPosition[a.springs.a[k]].x() + a.nodes.restPosition[a.springs.b[k]].x());
        EXPECT_DOUBLE_EQ(b.springs.stiffness[k], (mid < -0.0015 ? 5.0 : 1.0) * a.springs.stiffness[k]);
    }

    // Split a face on each side: the new springs and the new node take the scale where they are.
    cutting::CutModel organ = half->makeOrgan();
    const auto faceAt = [&](double x) {
        for (std::uint32_t f = 0; f < organ.mesh().faces.size(); ++f) {
            Vec3 c = Vec3::Zero();
            for (std::uint32_t v : organ.mesh().faces[f]) c += organ.mesh().positions[v] / 3;
            if (std::abs(c.x() - x) < 0.001 && std::abs(c.y()) < 0.002) return f;
        }
        return std::uint32_t{0};
    };
    const std::size_t springsBefore = organ.model().springs.size();
    const std::uint32_t left = organ.splitFace(faceAt(-0.01), Vec3(1, 1, 1) / 3);
    const std::uint32_t right = organ.splitFace(faceAt(0.01), Vec3(1, 1, 1) / 3);
    const physics::Springs& s = organ.model().springs;
    ASSERT_EQ(s.size(), springsBefore + 6);
    const double kLeft = s.stiffness[springsBefore] * s.restLength[springsBefore];
    const double kRight = s.stiffness[springsBefore + 3] * s.restLength[springsBefore + 3];
    EXPECT_NEAR(kLeft / kRight, 5.0, 1e-9) << "k·L of a new spring in the region, against one outside";
    const physics::Nodes& n = organ.model().nodes;
    EXPECT_NEAR((n.anchorStiffness[left] / n.mass[left]) / (n.anchorStiffness[right] / n.mass[right]), 5.0, 1e-9);
    EXPECT_NEAR((n.anchorDamping[left] / n.mass[left]) / (n.anchorDamping[right] / n.mass[right]), 2.0, 1e-9);
}

TEST_F(TissueRegions, AMeshRegionHoldsWhatIsInsideItsClosedSurface) {
    const mesh::SurfaceMesh ball = mesh::procedural::makeSphere(Vec3(0.01, 0, 0), 0.005, 16, 12);
    ASSERT_FALSE(mesh::io::saveMesh(dir / "tumour.obj", ball, {}).has_value());
    const auto scene = load("[[regions]]\nmesh = \"tumour.obj\"\nstiffness_scale = 3.0\n");
    ASSERT_TRUE(scene) << scene.error().toString();
    ASSERT_TRUE(scene->tissue);
    EXPECT_EQ(scene->tissue(Vec3(0.01, 0, 0)).stiffness, 3.0);
    EXPECT_EQ(scene->tissue(Vec3(0.01, 0, 0)).toughness, 1.0) << "only what the region sets";
    EXPECT_EQ(scene->tissue(Vec3(0.01, 0.004, 0)).stiffness, 3.0);
    EXPECT_EQ(scene->tissue(Vec3(0.01, 0.006, 0)).stiffness, 1.0);
    EXPECT_EQ(scene->tissue(Vec3(-0.01, 0, 0)).stiffness, 1.0);

    mesh::SurfaceMesh open = ball;
    open.faces.pop_back();
    ASSERT_FALSE(mesh::io::saveMesh(dir / "open.obj", open, {}).has_value());
    const auto refused = load("[[regions]]\nmesh = \"open.obj\"\n");
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().line, 1);
    EXPECT_NE(refused.error().message.find("regions[0].mesh: "), std::string::npos) << refused.error().toString();
    EXPECT_NE(refused.error().message.find("is not a closed surface"), std::string::npos);
}

TEST_F(TissueRegions, EveryMalformedKeyIsAnErrorAtItsLine) {
    const auto parse = [](const std::string& text) { return parseScene(text, "scene.toml", "/data"); };
    expectError(parse("regions = 3\n"), 1, "regions: expected a list of [[regions]] tables");
    expectError(parse("[[regions]]\nshape = \"cone\"\n"), 2, "regions[0].shape: 'cone' is not allowed");
    expectError(parse("[[regions]]\nstiffness_scale = 2.0\n"), 1, "regions[0]: needs a shape (sphere, box) or a mesh");
    expectError(parse("[[regions]]\nshape = \"sphere\"\ncenter_m = [0, 0, 0]\n"), 1, "a sphere needs radius_m");
    expectError(parse("[[regions]]\nshape = \"sphere\"\nradius_m = 0.01\n"), 1, "a sphere needs center_m");
    expectError(parse("[[regions]]\nshape = \"sphere\"\ncenter_m = [0, 0, 0]\nradius_m = 0.01\nsize_m = [1, 1, 1]\n"),
                5, "regions[0].size_m: a sphere has none");
    expectError(parse("[[regions]]\nshape = \"sphere\"\ncenter_m = [0, 0]\nradius_m = 0.01\n"), 3,
                "regions[0].center_m: expected three numbers");
    expectError(parse("[[regions]]\nshape = \"sphere\"\ncenter_m = [0, 0, 0]\nradius_m = 0\n"), 4,
                "regions[0].radius_m: 0 is out of range");
    expectError(parse("[[regions]]\nshape = \"box\"\ncenter_m = [0, 0, 0]\nsize_m = [0.01, -0.01, 0.01]\n"), 4,
                "regions[0].size_m: expected three sizes above 0");
    expectError(parse("[[regions]]\nshape = \"box\"\nmesh = \"t.obj\"\ncenter_m = [0, 0, 0]\nsize_m = [1, 1, 1]\n"), 3,
                "regions[0].mesh: a box has none");
    expectError(parse("[[regions]]\nmesh = \"t.obj\"\nradius_m = 0.01\n"), 3, "regions[0].radius_m: a mesh has none");
    expectError(parse("[[regions]]\nmesh = \"t.obj\"\nstiffness_scale = 0\n"), 3,
                "regions[0].stiffness_scale: 0 is out of range; allowed: 0.01 to 1000");
    expectError(parse("[[regions]]\nmesh = \"t.obj\"\ndamping_scale = \"high\"\n"), 3,
                "regions[0].damping_scale: expected a number");
    expectError(parse("[[regions]]\nmesh = \"t.obj\"\nhidden = \"yes\"\n"), 3,
                "regions[0].hidden: expected true or false");
    expectError(parse("[[regions]]\nmesh = \"t.obj\"\ntoughness_scale = 2000\n"), 3,
                "regions[0].toughness_scale: 2000 is out of range");
    expectError(parse("[[regions]]\nmesh = \"t.obj\"\nstifness_scale = 2\n"), 3, "regions[0].stifness_scale");
    const auto two = parse(
        "[[regions]]\nmesh = \"t.obj\"\n[[regions]]\nshape = \"box\"\ncenter_m = [0, 0, 0]\n"
        "size_m = [1, 2, 3]\nstiffness_scale = 4\ntoughness_scale = 2.5\n");
    ASSERT_TRUE(two) << two.error().toString();
    ASSERT_EQ(two->regions.size(), 2u);
    EXPECT_EQ(two->regions[0].mesh, "/data/t.obj") << "relative to the scene's folder";
    EXPECT_EQ(two->regions[1].shape, SceneRegion::Shape::Box);
    EXPECT_EQ(two->regions[1].size_m, Vec3(1, 2, 3));
    EXPECT_EQ(two->regions[1].stiffnessScale, 4.0);
    EXPECT_EQ(two->regions[1].toughnessScale, 2.5);
    EXPECT_EQ(two->regions[1].line, 3);
}

}  // namespace
}  // namespace hapticut::scene
