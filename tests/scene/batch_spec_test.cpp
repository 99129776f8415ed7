// Batch specs: a spec with every key read as written, and every kind of mistake an error at its line.
#include <gtest/gtest.h>

#include <fstream>

#include "hapticut/scene/batch_spec.h"
#include "test_support.h"

namespace hapticut::scene {
namespace {

using test::expectError;

class BatchSpecFile : public ::testing::Test {
protected:
    Result<BatchSpec, Error> read(const std::string& text) {
        std::ofstream(dir / "spec.toml") << text;
        return readBatchSpec(dir / "spec.toml");
    }
    test::ScratchDir dir;
};

TEST_F(BatchSpecFile, ReadsTheBaseRunAndTheSweepInTheSpecsOrder) {
    std::ofstream(dir / "press.csv") << "t,x,y,z\n0,0,0,0.1\n";
    const auto spec = read(
        "[batch]\nmodel = \"heart\"\ntriangles = 1619\ntrajectory = \"press.csv\"\ntool = \"probe\"\nsteps = 500\n"
        "integrator = \"implicit\"\nrate_hz = 500\n"
        "[sweep]\n\"material.positioning_stiffness_N_per_m3\" = [4.4e6, 8.8e6]\n"
        "\"device.stiffness_N_per_m\" = [200, 400, 800]\n\"simulation.integrator\" = [\"rk4\", \"implicit\"]\n"
        "\"device.workspace_offset_m\" = [[0.0, 0.5, 0.25]]\n");
    ASSERT_TRUE(spec.has_value()) << spec.error().toString();
    EXPECT_EQ(spec->model, "heart");
    EXPECT_EQ(spec->triangles, 1619);
    ASSERT_EQ(spec->sessions.size(), 1u);
    EXPECT_EQ(spec->sessions[0], dir / "press.csv") << "relative to the spec's folder";
    EXPECT_FALSE(spec->sessionsFromFolder);
    EXPECT_EQ(spec->tool, "probe");
    EXPECT_EQ(spec->steps, 500);
    EXPECT_EQ(spec->integrator, "implicit");
    EXPECT_EQ(spec->rate_hz, 500.0);
    ASSERT_EQ(spec->sweep.size(), 4u);
    EXPECT_EQ(spec->sweep[0].key, "material.positioning_stiffness_N_per_m3") << "the spec's order, not sorted";
    EXPECT_EQ(spec->sweep[0].line, 10);
    EXPECT_EQ(spec->sweep[0].values, (std::vector<std::string>{"4400000.0", "8800000.0"}));
    EXPECT_EQ(spec->sweep[1].values, (std::vector<std::string>{"200", "400", "800"}));
    EXPECT_EQ(spec->sweep[2].values, (std::vector<std::string>{"'rk4'", "'implicit'"}));
    EXPECT_EQ(spec->sweep[3].values, (std::vector<std::string>{"[ 0.0, 0.5, 0.25 ]"}));
}

TEST_F(BatchSpecFile, AFolderOfSessionsIsEachRecordingByName) {
    std::filesystem::create_directories(dir / "recordings");
    for (const char* name : {"b.csv", "a.csv", "notes.txt"}) std::ofstream(dir / "recordings" / name) << "t,x,y,z\n";
    const auto spec = read("[batch]\nsessions = \"recordings\"\n");
    ASSERT_TRUE(spec.has_value()) << spec.error().toString();
    EXPECT_TRUE(spec->sessionsFromFolder);
    EXPECT_EQ(spec->sessions,
              (std::vector<std::filesystem::path>{dir / "recordings" / "a.csv", dir / "recordings" / "b.csv"}));
    EXPECT_TRUE(spec->sweep.empty()) << "no sweep: one run a session";
}

TEST_F(BatchSpecFile, EveryMistakeIsAnErrorAtItsLine) {
    std::ofstream(dir / "press.csv") << "t,x,y,z\n";
    std::filesystem::create_directories(dir / "empty");
    expectError(read("[batch\n"), 1, "");
    expectError(read("[sweep]\n\"a.b\" = [1]\n"), 1, "no [batch] table");
    expectError(read("[batch]\n[runs]\nn = 1\n"), 2, "[batch] and [sweep] only");
    expectError(read("[batch]\nmodle = \"heart\"\n"), 2, "batch.modle is not a batch key (allowed: ");
    expectError(read("[batch]\nmodel = \"liver.obj\"\n"), 2, "no file ");
    expectError(read("[batch]\ntrajectory = \"missing.csv\"\n"), 2, "relative to the spec's folder");
    expectError(read("[batch]\nsessions = \"empty\"\n"), 2, "holds no recorded session");
    std::filesystem::create_directories(dir / "recordings");
    std::ofstream(dir / "recordings" / "a.csv") << "t,x,y,z\n";
    expectError(read("[batch]\ntrajectory = \"press.csv\"\nsessions = \"recordings\"\n"), 3, "not both");
    expectError(read("[batch]\ntriangles = \"many\"\n"), 2, "batch.triangles must be a whole number");
    expectError(read("[batch]\nsteps = 0\n"), 2, "at least 1");
    expectError(read("[batch]\nintegrator = \"fast\"\n"), 2, "'fast' is none of auto");
    expectError(read("[batch]\n\ntool = \"lancet\"\n"), 3, "batch.tool: ");
    expectError(read("[batch]\n[sweep]\n\"material.mass_kg\" = 2\n"), 3, "must be a list of the values");
    expectError(read("[batch]\n[sweep]\n\"material.mass_kg\" = []\n"), 3, "must be a list of the values");
    expectError(read("[batch]\n[sweep]\n\"material.mass_kg\" = [1]\n\"material.stifness\" = [1, 2]\n"), 4,
                "sweep \"material.stifness\" = 1: ");
    expectError(read("[batch]\n[sweep]\n\"device.stiffness_N_per_m\" = [200, -5]\n"), 3,
                "sweep \"device.stiffness_N_per_m\" = -5: ");
    const auto spec = read("[batch]\n[sweep]\n\"material.nope\" = [1]\n");
    ASSERT_FALSE(spec.has_value());
    EXPECT_EQ(spec.error().file, dir / "spec.toml") << "the spec's file, not the scene's overlay";
}

}  // namespace
}  // namespace hapticut::scene
