// Scene files: the shipped example, every kind of mistake with its key path and line, paths, placement.
#include <gtest/gtest.h>

#include <filesystem>

#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/scene/scene.h"
#include "hapticut/scene/scene_file.h"
#include "test_support.h"

namespace hapticut::scene {
namespace {

namespace fs = std::filesystem;

TEST(SceneFile, TheCommentedExampleIsTheBuiltInDefault) {
    const auto s = readScene(fs::path(HAPTICUT_SOURCE_DIR) / "assets/scenes/heart.toml");
    ASSERT_TRUE(s.has_value()) << s.error().toString();
    const SceneFile d = defaultScene();
    EXPECT_EQ(s->model, d.model);
    EXPECT_EQ(s->triangles, d.triangles);
    EXPECT_EQ(s->scheme, d.scheme);
    EXPECT_EQ(s->rate_hz, d.rate_hz);
    EXPECT_EQ(s->hapticThreadPriority, haptics::LoopConfig{}.hapticThreadPriority);
    EXPECT_DOUBLE_EQ(s->maxPhysicsStep_s, haptics::LoopConfig{}.maxPhysicsStep_s);
    EXPECT_EQ(s->solver.tolerance, physics::SolverSettings{}.tolerance);
    EXPECT_EQ(s->solver.forceTolerance_N, physics::SolverSettings{}.forceTolerance_N);
    EXPECT_EQ(s->solver.threads, physics::SolverSettings{}.threads);
    EXPECT_EQ(s->couplingStiffness_N_per_m, d.couplingStiffness_N_per_m);
    EXPECT_EQ(s->material.positioningStiffness_N_per_m3, physics::Material{}.positioningStiffness_N_per_m3);
    EXPECT_EQ(s->material.structuralStiffness_N, physics::Material{}.structuralStiffness_N);
    ASSERT_EQ(s->tools.size(), 2u);
    EXPECT_EQ(s->tools[0].name, "probe");
    EXPECT_EQ(s->tools[1].name, "scalpel");
    EXPECT_EQ(s->tools[1].threshold_N, d.tools[1].threshold_N);
    EXPECT_EQ(s->stereo, "off");
}

TEST(SceneFile, RelativePathsResolveAgainstTheScenesFolder) {
    const auto s = parseScene(
        "[model]\nsource = \"organs/liver.stl\"\n[device]\nbackend = \"replay\"\ntrajectory = \"../t.csv\"\n", "x.toml",
        "/data/scenes");
    ASSERT_TRUE(s.has_value()) << s.error().toString();
    EXPECT_EQ(s->model, "/data/scenes/organs/liver.stl");
    EXPECT_EQ(s->trajectory, "/data/t.csv");
}

// A script's or a sweep's settings go over the file's keys, each checked as a file's would be; a mistake
// in them names them, not the file.
TEST(SceneFile, AnOverlaySetsKeysOverTheFilesAndNamesItsOwnMistakes) {
    const std::string file = "[material]\nmass_kg = 0.3\nbulk_modulus_Pa = 1e5\n[simulation]\nrate_hz = 500\n";
    const auto s = parseScene(file, "x.toml", "/data", "material.mass_kg = 1.5\ndevice.stiffness_N_per_m = 200\n");
    ASSERT_TRUE(s.has_value()) << s.error().toString();
    EXPECT_EQ(s->material.totalMass_kg, 1.5);
    EXPECT_EQ(s->bulkModulus_Pa, 1e5) << "the file's other keys of that table stay";
    EXPECT_EQ(s->rate_hz, 500);
    EXPECT_EQ(s->couplingStiffness_N_per_m, 200);
    const auto threads = parseScene(file, "x.toml", "/data", "simulation.solver_threads = 3\n");
    ASSERT_TRUE(threads.has_value()) << threads.error().toString();
    EXPECT_EQ(threads->solver.threads, 3u);
    const auto normal = parseScene(file, "x.toml", "/data", "simulation.haptic_thread_priority = 0\n");
    ASSERT_TRUE(normal.has_value()) << normal.error().toString();
    Scene scene;
    scene.settings = *normal;
    EXPECT_EQ(scene.loopConfig().hapticThreadPriority, 0) << "the loop gets it";
    const auto shortSteps = parseScene(file, "x.toml", "/data", "simulation.max_physics_step_ms = 20\n");
    ASSERT_TRUE(shortSteps.has_value()) << shortSteps.error().toString();
    scene.settings = *shortSteps;
    EXPECT_DOUBLE_EQ(scene.loopConfig().maxPhysicsStep_s, 0.02) << "the loop gets it, in seconds";
    const auto multilevel = parseScene(file, "x.toml", "/data", "simulation.solver_preconditioner = \"multilevel\"\n");
    ASSERT_TRUE(multilevel.has_value()) << multilevel.error().toString();
    EXPECT_EQ(multilevel->solver.preconditioner, physics::Preconditioner::Multilevel);
    test::expectError(parseScene(file, "x.toml", "/data", "material.mass_kg = 1.5\nmaterial.mass_kilos = 2\n"), 2,
                      "material.mass_kilos");
    const auto outOfRange = parseScene(file, "x.toml", "/data", "simulation.rate_hz = 1e9\n");
    ASSERT_FALSE(outOfRange.has_value());
    EXPECT_EQ(outOfRange.error().file, kOverlayName);
    EXPECT_EQ(outOfRange.error().line, 1);
    const auto broken = parseScene(file, "x.toml", "/data", "material.mass_kg = = 1\n");
    ASSERT_FALSE(broken.has_value());
    EXPECT_EQ(broken.error().file, kOverlayName);
    const auto fileMistake = parseScene("[simulation]\nrate_hz = 1e9\n", "x.toml", "/data", "material.mass_kg = 1\n");
    ASSERT_FALSE(fileMistake.has_value());
    EXPECT_EQ(fileMistake.error().file, "x.toml") << "the file's own mistake still names the file";
    EXPECT_EQ(fileMistake.error().line, 2);
}

TEST(SceneFile, ACommandLinesSettingBecomesAnOverlayLine) {
    EXPECT_EQ(*settingLine("material.mass_kg=1.5"), "material.mass_kg = 1.5\n");
    EXPECT_EQ(*settingLine("model.translate_m=[0, 0.1, 0]"), "model.translate_m = [0, 0.1, 0]\n");
    EXPECT_EQ(*settingLine("simulation.integrator=rk4"), "simulation.integrator = \"rk4\"\n");
    EXPECT_EQ(*settingLine("model.source=a \"b\".obj"), "model.source = \"a \\\"b\\\".obj\"\n");
    for (const char* bad : {"material", "=1", "material..mass_kg=1", "material mass=1", ".material=1"})
        EXPECT_FALSE(settingLine(bad).has_value()) << bad;
    const auto s = parseScene("", "x.toml", "/data", *settingLine("simulation.integrator=rk4"));
    ASSERT_TRUE(s.has_value()) << s.error().toString();
    EXPECT_EQ(s->scheme, physics::Scheme::RungeKutta4);
}

TEST(SceneFile, MistakesNameTheKeyTheLineAndTheAllowedValues) {
    auto expectError = [](const std::string& text, int line, const std::string& fragment) {
        test::expectError(parseScene(text, "s.toml", "."), line, fragment);
    };
    expectError("[modle]\n", 1,
                "modle: unknown key; allowed here: device, devices, exercise, material, model, regions, rendering, "
                "simulation, tools");
    expectError("[model]\ntriangle = 5\n", 2,
                "model.triangle: unknown key; allowed here: center, fit_size_m, parts, rotate_deg, scale, source, "
                "translate_m, triangles");
    expectError("[device]\nstiffness_N_per_m = \"hard\"\n", 2, "device.stiffness_N_per_m: expected a number");
    expectError("[simulation]\nrate_hz = 50\n", 2, "simulation.rate_hz: 50 is out of range; allowed: 100 to 10000");
    expectError("[simulation]\nintegrator = \"verlet\"\n", 2,
                "'verlet' is not allowed; allowed: auto, euler, implicit, midpoint, rk4, symplectic");
    expectError("[simulation]\nsolver_max_iterations = 0\n", 2,
                "simulation.solver_max_iterations: 0 is out of range; allowed: 1 to 10000");
    expectError("[simulation]\nsolver_threads = 300\n", 2,
                "simulation.solver_threads: 300 is out of range; allowed: 0 to 256");
    expectError("[simulation]\nsolver_force_tolerance_N = -1e-6\n", 2,
                "simulation.solver_force_tolerance_N: -1e-06 is out of range; allowed: 0 to 1");
    expectError("[simulation]\nhaptic_thread_priority = 100\n", 2,
                "simulation.haptic_thread_priority: 100 is out of range; allowed: 0 to 99");
    expectError("[simulation]\nmax_physics_step_ms = 0.5\n", 2,
                "simulation.max_physics_step_ms: 0.5 is out of range; allowed: 1 to 1000");
    expectError("[simulation]\nactive_region = 1\n", 2, "simulation.active_region: expected true or false");
    expectError("[simulation]\nsolver_preconditioner = \"jacobi\"\n", 2,
                "simulation.solver_preconditioner: 'jacobi' is not allowed; allowed: auto, block-jacobi, multilevel");
    expectError("[model]\ntranslate_m = [1, 2]\n", 2, "model.translate_m: expected three numbers");
    expectError("[model]\ntranslate_m = [1, \"a\", 2]\n", 2, "expected three finite numbers");
    expectError("[device]\nbackend = \"replay\"\n", 1, "device.trajectory: the replay backend needs a trajectory file");
    expectError("[device]\nstatic_friction = 0.2\ndynamic_friction = 0.5\n", 1,
                "must not exceed device.static_friction");
    expectError("[[tools]]\nthreshold_N = 3\n", 1, "tools[0].name: every tool needs a name");
    expectError("[[tools]]\nname = \"knife\"\nsharpness = 3\n", 3, "tools[0].sharpness: unknown key");
    expectError("tools = 3\n", 1, "tools: expected a list");
    expectError("model = 3\n", 1, "model: expected a table");
    expectError("[simulation\n", 1, "expected ']'");
    expectError("[material]\nmass_kg = nan\n", 2, "material.mass_kg: nan is out of range");
    // A value just past a bound shows its own digits, not the bound's, and counts are whole.
    expectError("[model]\ntriangles = 20000000.9\n", 2,
                "model.triangles: 20000000.9 is out of range; allowed: 12 to 20000000");
    expectError("[model]\ntriangles = 2000.5\n", 2, "model.triangles: expected a whole number, found 2000.5");
    expectError("[simulation]\nsolver_max_iterations = 10.5\n", 2, "expected a whole number, found 10.5");
    expectError("[material]\nmass_kg = -1\n", 2, "out of range");
    expectError("[material]\ntoughness_J_per_m2 = 0\n", 2, "material.toughness_J_per_m2: 0 is out of range");
}

TEST(SceneFile, TheTissuesToughnessGoesToEveryBladeAndIsOtherwiseTheToolsOwn) {
    const auto given = parseScene("[material]\ntoughness_J_per_m2 = 350\n", "x.toml", "/data");
    ASSERT_TRUE(given.has_value()) << given.error().toString();
    EXPECT_EQ(given->toughness_J_per_m2, 350.0);
    const auto none = parseScene("[material]\nmass_kg = 0.2\n", "x.toml", "/data");
    ASSERT_TRUE(none.has_value());
    EXPECT_FALSE(none->toughness_J_per_m2.has_value()) << "from each tool's threshold";
}

TEST(SceneFile, ToolsHaveTipsAndTheTissueMayLimitItsStrain) {
    const SceneFile d = defaultScene();
    EXPECT_EQ(d.tools[0].tipRadius_m, mesh::procedural::kProbeTipRadius_m);
    EXPECT_EQ(d.tools[1].tipRadius_m, mesh::procedural::kScalpelTipRadius_m);
    EXPECT_EQ(d.strainLimit, 0) << "off unless asked for";
    const auto given = parseScene(
        "[material]\nstrain_limit = 0.1\n[[tools]]\nname = \"probe\"\ntip_radius_m = 0\n[[tools]]\nname = "
        "\"knife\"\nfile = \"knife.txt\"\nthreshold_N = 3\n[[tools]]\nname = \"pusher\"\nfile = \"p.txt\"\n",
        "x.toml", "/data");
    ASSERT_TRUE(given.has_value()) << given.error().toString();
    EXPECT_EQ(given->strainLimit, 0.1);
    EXPECT_EQ(given->tools[0].tipRadius_m, 0) << "the thesis's point contact";
    EXPECT_EQ(given->tools[1].tipRadius_m, mesh::procedural::kScalpelTipRadius_m) << "a tool that cuts: a blade's tip";
    EXPECT_EQ(given->tools[2].tipRadius_m, mesh::procedural::kProbeTipRadius_m) << "one that never cuts: a probe's";
    auto expectError = [](const std::string& text, int line, const std::string& fragment) {
        test::expectError(parseScene(text, "s.toml", "."), line, fragment);
    };
    expectError("[[tools]]\nname = \"probe\"\ntip_radius_m = 0.2\n", 3,
                "tools[0].tip_radius_m: 0.2 is out of range; allowed: 0 to 0.05");
    expectError("[material]\nstrain_limit = -0.1\n", 2, "material.strain_limit: -0.1 is out of range");
}

TEST(SceneFile, PlacementScalesThenRotatesThenTranslates) {
    SceneFile s = defaultScene();
    s.scale = 2;
    s.rotate_deg = Vec3(0, 0, 90);
    s.translate_m = Vec3(1, 0, 0);
    std::vector<Vec3> p = {Vec3(1, 0, 0)};
    applyPlacement(s, p);
    EXPECT_LT((p[0] - Vec3(1, 2, 0)).norm(), 1e-12);
}

TEST(SceneFile, EachDeviceHasItsOwnTableWithItsToolCouplingLimitsAndMapping) {
    const auto s = readScene(fs::path(HAPTICUT_SOURCE_DIR) / "assets/scenes/two-hands.toml");
    ASSERT_TRUE(s.has_value()) << s.error().toString();
    ASSERT_EQ(s->devices.size(), 2u);
    const SceneDevice& first = s->devices[0];
    EXPECT_EQ(first.device.kind, haptics::DeviceKind::Replay);
    EXPECT_EQ(fs::path(first.device.argument).lexically_normal(),
              (fs::path(HAPTICUT_SOURCE_DIR) / "assets/trajectories/cut-front.csv").lexically_normal());
    EXPECT_EQ(first.tool, "scalpel");
    EXPECT_EQ(first.couplingStiffness_N_per_m, 400);
    EXPECT_TRUE(first.fitWorkspace);
    const SceneDevice& second = s->devices[1];
    EXPECT_EQ(second.tool, "probe");
    EXPECT_EQ(second.couplingStiffness_N_per_m, 300);
    EXPECT_FALSE(second.couplingDamping_Ns_per_m) << "not given: the loop's";
    EXPECT_EQ(second.maxForce_N, 2.0);

    const auto mapped = parseScene(
        "[[devices]]\ndevice = \"openhaptics:Left Touch\"\nworkspace = \"mapped\"\nworkspace_scale = 0.5\n"
        "workspace_offset_m = [0, 0, 0.1]\nsdl_control = \"rate\"\n",
        "s.toml", ".");
    ASSERT_TRUE(mapped.has_value()) << mapped.error().toString();
    EXPECT_EQ(mapped->devices[0].device.argument, "Left Touch");
    EXPECT_FALSE(mapped->devices[0].fitWorkspace);
    EXPECT_EQ(mapped->devices[0].workspace.scale, 0.5);
    EXPECT_EQ(mapped->devices[0].workspace.offset_m, Vec3(0, 0, 0.1));
    EXPECT_EQ(mapped->devices[0].sdlControl, "rate");
}

TEST(SceneFile, DeviceTablesWithMistakesNameTheKeyAndLine) {
    auto expectError = [](const std::string& text, int line, const std::string& fragment) {
        test::expectError(parseScene(text, "s.toml", "."), line, fragment);
    };
    const std::string one = "[[devices]]\ndevice = \"virtual\"\n";
    expectError(one + one + one, 1, "devices: 3 devices; at most 2, one per hand");
    expectError("[device]\nbackend = \"virtual\"\n" + one, 3,
                "either one [device] table or [[devices]] tables, not both");
    expectError("[[devices]]\ntool = \"probe\"\n", 1, "devices[0].device: every device needs a name");
    expectError("[[devices]]\ndevice = \"phantom\"\n", 2, "devices[0].device: device 'phantom': unknown kind");
    expectError(one + "tool = \"chisel\"\n", 3,
                "devices[0].tool: 'chisel' is not one of the scene's tools: probe, scalpel");
    expectError(one + "workspace = \"stretched\"\n", 3, "'stretched' is not allowed; allowed: fit, mapped");
    expectError(one + "max_force_N = 80\n", 3, "devices[0].max_force_N: 80 is out of range");
    expectError(one + "colour = \"red\"\n", 3, "devices[0].colour: unknown key");
}

TEST(SceneFile, KeysNestedTooDeepAreRefusedBeforeTheParserRecursesIntoThem) {
    // A table header or a dotted key 100,000 parts long overflowed the stack inside the TOML parser.
    std::string parts = "a";
    for (int i = 1; i < 100'000; ++i) parts += ".a";
    test::expectError(parseScene("[" + parts + "]\n", "s.toml", "."), 1, "a key of 100000 dotted parts; at most 64");
    test::expectError(parseScene("# deep below\n\n" + parts + " = 1\n", "s.toml", "."), 3,
                      "a key of 100000 dotted parts");
    // Dots in strings, numbers and comments are no keys' parts.
    const std::string dots(200, '.');
    const auto fine =
        parseScene("[model]  # " + dots + "\nsource = \"" + dots + "obj\"\nscale = 1.5\n", "s.toml", "/d");
    ASSERT_TRUE(fine.has_value()) << fine.error().toString();
    EXPECT_EQ(fine->scale, 1.5);
}

TEST(SceneFile, MissingFileIsAClearError) {
    const auto r = readScene("/nonexistent/scene.toml");
    ASSERT_FALSE(r.has_value());
    EXPECT_NE(r.error().message.find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace hapticut::scene
