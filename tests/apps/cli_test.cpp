// The hapticut executable end to end: reports, conversions, errors and exit codes, shipped assets.
#include <gtest/gtest.h>

#include <chrono>

#include <sys/wait.h>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace {

namespace fs = std::filesystem;

struct CliResult {
    int exitCode;
    std::string out, err;
};

using hapticut::test::slurp;

class Cli : public ::testing::Test {
protected:
    CliResult run(const std::string& args) const { return run_raw(std::string(HAPTICUT_EXE) + " " + args); }
    CliResult run_raw(const std::string& command) const {
        const std::string cmd = command + " >" + (dir_ / "out").string() + " 2>" + (dir_ / "err").string();
        const int status = std::system(cmd.c_str());
        return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir_ / "out"), slurp(dir_ / "err")};
    }
    CliResult run_with_env(const std::string& env, const std::string& args) const {
        return run_raw(env + HAPTICUT_EXE + " " + args);
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    hapticut::test::ScratchDir scratch_;
    const fs::path& dir_ = scratch_.path();
};

TEST_F(Cli, RunWritesAReportWithEveryKey) {
    const CliResult r =
        run("run --steps 400 --force-at 0,-0.01,0.05 --force 0,0,-1 --force-until 0.2 --report " + path("r.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(path("r.json")));
    for (const char* key :
         {"model", "vertices", "faces", "springs", "integrator", "dt", "steps", "sim_time_s", "wall_time_s", "step_us",
          "max_displacement_m", "final_max_displacement_m", "kinetic_energy_end_J", "nan_events"})
        EXPECT_TRUE(j.contains(key)) << key;
    for (const char* key : {"mean", "p50", "p99", "max"}) EXPECT_TRUE(j["step_us"].contains(key)) << key;
    EXPECT_EQ(j["model"], "heart");
    // What produced it: the build, the command as given, and the machine.
    const auto& made = j["provenance"];
    EXPECT_EQ(made["hapticut"], "0.1.0");
    EXPECT_FALSE(made["commit"].get<std::string>().empty());
    EXPECT_NE(made["command"].get<std::string>().find("run --steps 400 --force-at 0,-0.01,0.05"), std::string::npos)
        << made["command"];
    EXPECT_FALSE(made["cpu"].get<std::string>().empty());
    EXPECT_FALSE(made["simd_target"].get<std::string>().empty());
    EXPECT_NEAR(j["faces"].get<double>(), 1619, 0.02 * 1619);
    EXPECT_EQ(j["integrator"], "rk4");
    EXPECT_EQ(j["steps"], 400);
    EXPECT_DOUBLE_EQ(j["sim_time_s"].get<double>(), 0.4);
    EXPECT_EQ(j["nan_events"], 0);
    // The press indents the heart by millimetres, and it comes back after release.
    EXPECT_GT(j["force"]["node_displacement_at_release_m"].get<double>(), 1e-3);
    EXPECT_GT(j["max_displacement_m"].get<double>(), 1e-3);
    EXPECT_LT(j["final_max_displacement_m"].get<double>(), 0.2 * j["max_displacement_m"].get<double>());
    EXPECT_GT(j["force"]["recovery_time_s"].get<double>(), 0.0);
    EXPECT_LT(j["force"]["recovery_time_s"].get<double>(), 0.2);
    EXPECT_NE(r.out.find("pressed node"), std::string::npos);
}

TEST_F(Cli, InfoReportsTheHeartAsClosedAndManifold) {
    const CliResult r = run("info heart --triangles 2000 --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* key : {"vertices", "faces", "edges", "boundary_edges", "closed", "manifold", "oriented",
                            "components", "euler_characteristic", "bbox_min", "bbox_max", "min_angle_deg"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["closed"], true);
    EXPECT_EQ(j["manifold"], true);
    EXPECT_EQ(j["euler_characteristic"], 2);
    EXPECT_NEAR(j["faces"].get<double>(), 2000, 40);
}

TEST_F(Cli, ConvertsThroughEveryFormatAndKeepsTheMesh) {
    ASSERT_EQ(run("convert heart " + path("h.obj")).exitCode, 0);
    ASSERT_EQ(run("convert " + path("h.obj") + " " + path("h.ply")).exitCode, 0);
    const CliResult r = run("convert " + path("h.ply") + " " + path("h.txt"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto direct = nlohmann::json::parse(run("info heart --json").out);
    const auto converted = nlohmann::json::parse(run("info " + path("h.txt") + " --json").out);
    for (const char* key : {"vertices", "faces", "edges", "closed", "manifold", "oriented", "bbox_min", "bbox_max"})
        EXPECT_EQ(direct[key], converted[key]) << key;
    // A run on the converted file works too.
    EXPECT_EQ(run("run --model " + path("h.txt") + " --steps 20").exitCode, 0);
}

TEST_F(Cli, MalformedFileGivesFileLineMessageAndNonZeroExit) {
    std::ofstream(path("bad.txt")) << "physics\n1 2 3 4 5\nvertices 2\n0 0 0\n0 zero 0\nfaces 0\nnormals 0\nedges 0\n";
    for (const std::string cmd : {"info ", "run --model ", "convert "}) {
        const CliResult r = run(cmd + path("bad.txt") + (cmd == "convert " ? " " + path("x.obj") : ""));
        EXPECT_EQ(r.exitCode, 1) << cmd;
        EXPECT_NE(r.err.find("bad.txt:5: expected a finite number for y, found 'zero'"), std::string::npos) << r.err;
    }
    EXPECT_FALSE(fs::exists(path("x.obj")));
}

TEST_F(Cli, BadArgumentsAreExplained) {
    CliResult r = run("run --integrator leapfrog");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("unknown integrator 'leapfrog'"), std::string::npos) << r.err;
    r = run("run --force-at 1,2 --force 0,0,1");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("three numbers"), std::string::npos) << r.err;
    r = run("info " + path("missing.obj"));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("missing.obj: cannot open"), std::string::npos) << r.err;
    r = run("convert heart " + path("x.stl"));  // STL is read, not written
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("expected .txt (thesis format), .obj or .ply"), std::string::npos) << r.err;
}

TEST_F(Cli, EveryMistakeInTheArgumentsExitsWithTwoAndSaysWhat) {
    const struct {
        std::string command, says;
    } cases[] = {
        {"rnu --steps 1", "'rnu' is not a command; did you mean 'run'?"},
        {"sok --strokes 1", "did you mean 'soak'?"},
        {"frobnicate", "'frobnicate' is not a command\ncommands: "},
        {"run --dt abc", "--dt: expected a number, found 'abc'"},
        {"run --steps -5", "--steps: -5 is out of range; allowed: 0 to 1e+09"},
        {"run --bogus", "--bogus"},
        {"", "A subcommand is required"},
        {"soak --strokes", "--strokes"},
    };
    for (const auto& c : cases) {
        const CliResult r = run(c.command);
        EXPECT_EQ(r.exitCode, 2) << c.command << ": " << r.err;
        EXPECT_NE(r.err.find(c.says), std::string::npos) << c.command << ": " << r.err;
    }
    const CliResult viwe = run("viwe");
    EXPECT_EQ(viwe.exitCode, 2);
    if (viwe.err.find("commands: view") != std::string::npos) {  // built with the viewer
        EXPECT_NE(viwe.err.find("did you mean 'view'?"), std::string::npos) << viwe.err;
    }
    EXPECT_EQ(run("--version").exitCode, 0);
    EXPECT_EQ(run("run --help").exitCode, 0);
}

TEST_F(Cli, OutputsThatCannotBeWrittenAreRefusedBeforeTheRunStarts) {
    const std::string missing = path("no-such-folder") + "/r.json";
    const struct {
        std::string command, says;
    } cases[] = {
        {"run --steps 100000000 --report " + missing, "no-such-folder/r.json: cannot write it: there is no folder"},
        {"run --trajectory " + std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/press-front.csv --force-log " +
             path(""),
         "is a folder, expected a file"},
        {"soak --strokes 100000000 --report " + missing, "there is no folder"},
        {"convert heart " + path("no-such-folder") + "/h.obj", "there is no folder"},
        {"bench --json " + missing, "there is no folder"},
        {"screenshot --out " + path("shot.jpg"), "shot.jpg: cannot write it: expected a .png file"},
    };
    for (const auto& c : cases) {
        const auto start = std::chrono::steady_clock::now();
        const CliResult r = run(c.command);
        EXPECT_EQ(r.exitCode, 2) << c.command << ": " << r.err;
        if (r.err.find("'screenshot' is not a command") != std::string::npos) continue;  // built without the viewer
        EXPECT_NE(r.err.find(c.says), std::string::npos) << c.command << ": " << r.err;
        // A hundred million steps or strokes would take hours: refused before any of them.
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 20) << c.command;
    }
}

TEST_F(Cli, AMillimetreModelIsWarnedAboutAndLoadsRightWithUnits) {
    // The heart written in millimetres, as segmentation tools write organs.
    ASSERT_EQ(run("convert heart " + path("h.obj")).exitCode, 0);
    {
        std::ifstream in(path("h.obj"));
        std::ofstream out(path("mm.obj"));
        for (std::string line; std::getline(in, line);) {
            if (line.rfind("v ", 0) == 0) {
                std::istringstream v(line.substr(2));
                double x, y, z;
                v >> x >> y >> z;
                out << "v " << x * 1000 << " " << y * 1000 << " " << z * 1000 << "\n";
            } else {
                out << line << "\n";
            }
        }
    }
    CliResult r = run("info " + path("mm.obj"));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("give --units mm (it is then 12 cm across)"), std::string::npos) << r.err;
    r = run("info --units mm --json " + path("mm.obj"));
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    const std::string trajectory = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/press-front.csv";
    r = run("run --model " + path("mm.obj") + " --units mm --trajectory " + trajectory + " --report " + path("r.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    std::ifstream report(path("r.json"));
    const auto j = nlohmann::json::parse(report);
    EXPECT_GT(j["contact_steps"].get<long>(), 500) << "the shipped press reaches the organ in metres";
    // The same press in millimetres never comes near the organ, and says so.
    r = run("run --model " + path("mm.obj") + " --units mm --scale 1 --force-at 0,-10,50 --force 0,0,-1 --steps 5");
    EXPECT_NE(r.err.find("--force-at 0,-10,50 never comes near the model"), std::string::npos) << r.err;
    EXPECT_EQ(run("run --units inch --steps 1").exitCode, 2);
}

TEST_F(Cli, ShippedAssetsAreWhatTheCodeGenerates) {
    const CliResult r = run("assets --out " + dir_.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* file :
         {"models/heart.txt", "models/liver.obj", "models/kidney.obj", "tools/scalpel.txt", "tools/probe.txt",
          "trajectories/press-front.csv", "trajectories/stroke-front.csv", "trajectories/cut-front.csv",
          "trajectories/cut-liver.csv", "trajectories/press-kidney.csv", "sessions/incision-front.csv",
          "sessions/incision-front-aside.csv", "sessions/palpation-lump.csv"})
        EXPECT_TRUE(slurp(fs::path(HAPTICUT_SOURCE_DIR) / "assets" / file) == slurp(dir_ / file))
            << file << " is stale: run 'hapticut assets' and commit the result";
    const auto heart =
        nlohmann::json::parse(run(std::string("info ") + HAPTICUT_SOURCE_DIR + "/assets/models/heart.txt --json").out);
    EXPECT_EQ(heart["closed"], true);
    EXPECT_NEAR(heart["faces"].get<double>(), 1619, 0.02 * 1619);
    // The ready organs: two closed parts each, no sliver, the triangles the assets command asks for.
    for (const auto& [organ, triangles] : {std::pair{"liver", 8000}, {"kidney", 4000}}) {
        const auto j = nlohmann::json::parse(
            run(std::string("info ") + HAPTICUT_SOURCE_DIR + "/assets/models/" + organ + ".obj --json").out);
        EXPECT_EQ(j["closed"], true) << organ;
        EXPECT_EQ(j["oriented"], true) << organ;
        EXPECT_GE(j["min_angle_deg"].get<double>(), 25) << organ;
        EXPECT_NEAR(j["faces"].get<double>(), triangles, 0.05 * triangles) << organ;
        ASSERT_EQ(j["parts"].size(), 2u) << organ;
        for (const auto& part : j["parts"]) EXPECT_EQ(part["closed"], true) << organ << " " << part["name"];
    }
    const auto scalpel =
        nlohmann::json::parse(run(std::string("info ") + HAPTICUT_SOURCE_DIR + "/assets/tools/scalpel.txt --json").out);
    EXPECT_EQ(scalpel["tool_threshold_N"], 2.0);
}

TEST_F(Cli, ConvertsAnStlWithRepairUnitBoxAndPhysics) {
    // A tetrahedron in ASCII STL (one vertex per corner), one face inside out.
    const char* stl =
        "solid t\n"
        "facet normal 0 0 0\nouter loop\nvertex 1 1 1\nvertex 1 -1 -1\nvertex -1 1 -1\nendloop\nendfacet\n"
        "facet normal 0 0 0\nouter loop\nvertex 1 1 1\nvertex 1 -1 -1\nvertex -1 -1 1\nendloop\nendfacet\n"
        "facet normal 0 0 0\nouter loop\nvertex 1 1 1\nvertex -1 1 -1\nvertex -1 -1 1\nendloop\nendfacet\n"
        "facet normal 0 0 0\nouter loop\nvertex 1 -1 -1\nvertex -1 -1 1\nvertex -1 1 -1\nendloop\nendfacet\n"
        "endsolid t\n";
    std::ofstream(path("t.stl")) << stl;
    const CliResult r =
        run("convert " + path("t.stl") + " " + path("t.txt") + " --repair --fit-unit-box --mass 2 --ks 30");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("flipped"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(run("info " + path("t.txt") + " --json").out);
    EXPECT_EQ(j["vertices"], 4);
    EXPECT_EQ(j["faces"], 4);
    EXPECT_EQ(j["closed"], true);
    EXPECT_EQ(j["oriented"], true);
    EXPECT_DOUBLE_EQ(j["physics"]["mass"].get<double>(), 2.0);
    EXPECT_DOUBLE_EQ(j["physics"]["ks"].get<double>(), 30.0);
    EXPECT_DOUBLE_EQ(j["bbox_max"][0].get<double>() - j["bbox_min"][0].get<double>(), 1.0);
    // The STL runs directly too.
    EXPECT_EQ(run("run --model " + path("t.stl") + " --steps 10").exitCode, 0);
}

// A mesh remeshed on the way through: about the triangles asked for, closed and oriented, no sliver, and
// the figures printed; a target length works the same; the two together, or nonsense, are refused.
TEST_F(Cli, ConvertRemeshesToATriangleCountOrAnEdgeLength) {
    const CliResult r = run("convert heart --triangles 9714 --remesh 3000 " + path("r.obj"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("remeshed to"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("distance to the input"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(run("info " + path("r.obj") + " --json").out);
    EXPECT_NEAR(j["faces"].get<double>(), 3000, 450);
    EXPECT_EQ(j["closed"], true);
    EXPECT_EQ(j["oriented"], true);
    EXPECT_GT(j["min_angle_deg"].get<double>(), 15);

    ASSERT_EQ(run("convert heart --target-edge 0.004 " + path("e.obj")).exitCode, 0);
    const auto e = nlohmann::json::parse(run("info " + path("e.obj") + " --json").out);
    EXPECT_NEAR(e["mean_edge_length_m"].get<double>(), 0.004, 0.0006);

    // A flattened tetrahedron: one face all but a line. Loading it says so and offers the remeshing;
    // the heart, well shaped, gets no such advice.
    std::ofstream(path("flat.obj")) << "v 0 0 0\nv 0.05 0 0\nv 0 0.05 0\nv 0.025 0.025 0.0002\n"
                                       "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    const CliResult flat = run("info " + path("flat.obj") + " --json");
    EXPECT_NE(flat.err.find("badly shaped for simulation"), std::string::npos) << flat.err;
    EXPECT_NE(flat.err.find("--remesh"), std::string::npos) << flat.err;
    EXPECT_TRUE(nlohmann::json::parse(flat.out)["shape_advice"].is_string());
    EXPECT_TRUE(nlohmann::json::parse(run("info heart --json").out)["shape_advice"].is_null());

    // The same in millimetres, read with --units mm: the advice and the physics are the metre file's.
    // They were once worked out before the units, and gave edges a thousand times too long and springs
    // of a thousandth of the stiffness; `convert` wrote those springs into a thesis file.
    std::ofstream(path("flat-mm.obj")) << "v 0 0 0\nv 50 0 0\nv 0 50 0\nv 25 25 0.2\n"
                                          "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    const CliResult mm = run("info " + path("flat-mm.obj") + " --units mm --json");
    ASSERT_EQ(mm.exitCode, 0) << mm.err;
    const auto metres = nlohmann::json::parse(flat.out), millimetres = nlohmann::json::parse(mm.out);
    EXPECT_EQ(millimetres["shape_advice"], metres["shape_advice"]);
    EXPECT_NE(mm.err.find("against a mean of 46.1 mm"), std::string::npos) << mm.err;
    for (const char* constant : {"ks", "kd", "kp", "kdp"})
        EXPECT_NEAR(millimetres["physics"][constant].get<double>(), metres["physics"][constant].get<double>(),
                    1e-9 * metres["physics"][constant].get<double>())
            << constant;
    ASSERT_EQ(run("convert " + path("flat-mm.obj") + " --units mm " + path("flat.txt")).exitCode, 0);
    ASSERT_EQ(run("convert " + path("flat.obj") + " " + path("flat-m.txt")).exitCode, 0);
    const auto thesis = nlohmann::json::parse(run("info " + path("flat.txt") + " --json").out);
    EXPECT_NEAR(thesis["physics"]["kp"].get<double>(), metres["physics"]["kp"].get<double>(),
                1e-6 * metres["physics"]["kp"].get<double>());

    EXPECT_EQ(run("convert heart --remesh 3000 --target-edge 0.004 " + path("x.obj")).exitCode, 2);
    EXPECT_EQ(run("convert heart --target-edge -1 " + path("x.obj")).exitCode, 2);
    EXPECT_EQ(run("convert heart --remesh 2 " + path("x.obj")).exitCode, 2);
    EXPECT_FALSE(fs::exists(path("x.obj")));
}

// The remesher writes its vertices in no spatial order: loading the file renumbers them (mesh/vertex_order.h),
// says so, and bench measures a user's model as it loads for a run.
TEST_F(Cli, ARemeshedModelIsRenumberedForLocalityAndBenchMeasuresIt) {
    ASSERT_EQ(run("convert heart --remesh 3000 " + path("r.obj")).exitCode, 0);
    const auto info = nlohmann::json::parse(run("info " + path("r.obj") + " --json").out);
    EXPECT_EQ(info["vertex_order"]["renumbered"], true);
    EXPECT_LT(info["vertex_order"]["mean_edge_span_after"].get<double>(),
              0.25 * info["vertex_order"]["mean_edge_span_before"].get<double>());
    EXPECT_EQ(nlohmann::json::parse(run("info heart --json").out)["vertex_order"]["renumbered"], false);
    EXPECT_NE(run("info " + path("r.obj")).out.find("vertex order: renumbered for locality"), std::string::npos);
    EXPECT_NE(run("info heart").out.find("vertex order: kept,"), std::string::npos);

    const CliResult b =
        run("bench --model " + path("r.obj") + " --integrators rk4 --seconds 0.02 --json " + path("b.json"));
    ASSERT_EQ(b.exitCode, 0) << b.err;
    const auto j = nlohmann::json::parse(slurp(path("b.json")));
    EXPECT_EQ(j["vertex_order"]["renumbered"], true);
    ASSERT_EQ(j["results"].size(), 1u);
    EXPECT_EQ(j["results"][0]["triangles"], info["faces"]);
    EXPECT_EQ(j["results"][0]["integrator"], "rk4");
    ASSERT_GT(j["solver_kernels"].size(), 0u);
    EXPECT_GT(j["solver_kernels"][0]["assembly_us"].get<double>(), 0.0);
    // A CG iteration is the product and its two passes.
    EXPECT_GT(j["solver_kernels"][0]["cg_passes_us"].get<double>(), 0.0);
    EXPECT_GT(j["solver_kernels"][0]["cg_iteration_us"].get<double>(),
              j["solver_kernels"][0]["product_us"].get<double>());

    const CliResult heartOnly = run("bench --model " + path("r.obj") + " --cutting");
    EXPECT_EQ(heartOnly.exitCode, 2);
    EXPECT_NE(heartOnly.err.find("leave them out with --model"), std::string::npos) << heartOnly.err;
    const CliResult missing = run("bench --model " + path("none.obj"));
    EXPECT_EQ(missing.exitCode, 1);
    EXPECT_NE(missing.err.find("none.obj"), std::string::npos) << missing.err;
}

// The haptics bench says how often the machine took the processor away, and times each proxy update
// three times, so that the p99 of the update's own work can be told from the machine's gaps; the cutting
// bench says what touching memory again after a sleep costs here.
TEST_F(Cli, TheBenchReportsWhatTheMachineTakesAndTheProxysOwnWork) {
    const CliResult b =
        run("bench --triangles 1619 --integrators euler --threads 1 --haptics --cutting --seconds 0.05 --json " +
            path("h.json"));
    ASSERT_EQ(b.exitCode, 0) << b.err;
    EXPECT_NE(b.out.find("clock gaps over 1 us"), std::string::npos) << b.out;
    EXPECT_NE(b.out.find("left alone while the thread slept"), std::string::npos) << b.out;
    const auto j = nlohmann::json::parse(slurp(path("h.json")));
    const auto& gaps = j["clock_gaps"];
    EXPECT_GT(gaps["clock_reads_per_s"].get<double>(), 1e5);  // a clock read is well under 10 us anywhere
    EXPECT_GE(gaps["gaps_per_s"].get<double>(), 0.0);
    EXPECT_GE(gaps["stolen_share"].get<double>(), 0.0);
    EXPECT_LT(gaps["stolen_share"].get<double>(), 1.0);
    ASSERT_EQ(j["haptics"].size(), 1u);
    const auto& proxy = j["haptics"][0];
    // Each update's best is at most its wall time, so every rank of the one is at most the other's.
    EXPECT_LE(proxy["proxy_update_best_of_3_us"]["p99"].get<double>(), proxy["proxy_update_us"]["p99"].get<double>());
    EXPECT_LE(proxy["proxy_update_best_of_3_us"]["mean"].get<double>(), proxy["proxy_update_us"]["mean"].get<double>());
    EXPECT_GT(proxy["proxy_update_best_of_3_us"]["p50"].get<double>(), 0.0);
    const auto& touches = j["idle_page_touches"];
    EXPECT_EQ(touches["pages"], 2000);
    EXPECT_GT(touches["p50_us"].get<double>(), 0.0);
    EXPECT_LE(touches["p50_us"].get<double>(), touches["p99_us"].get<double>());
    EXPECT_LE(touches["p99_us"].get<double>(), touches["max_us"].get<double>());
    EXPECT_GE(touches["slow_share"].get<double>(), 0.0);
    EXPECT_LE(touches["slow_share"].get<double>(), 1.0);
    ASSERT_EQ(j["cutting"].size(), 1u);
    EXPECT_GT(j["cutting"][0]["cut_events"].get<int>(), 0);
}

// Any scene key from the command line, spelt as in a scene file and checked as a file's would be.
TEST_F(Cli, SetLaysSceneKeysOverTheScenes) {
    const std::string press = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/press-front.csv";
    ASSERT_EQ(run("run --trajectory " + press + " --report " + path("soft.json")).exitCode, 0);
    const CliResult r = run("run --trajectory " + press +
                            " --set material.positioning_stiffness_N_per_m3=1.76e7 --set device.stiffness_N_per_m=200"
                            " --set simulation.integrator=implicit --solver-threads 3 --report " +
                            path("stiff.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto soft = nlohmann::json::parse(slurp(path("soft.json")));
    const auto stiff = nlohmann::json::parse(slurp(path("stiff.json")));
    EXPECT_EQ(stiff["coupling_stiffness_N_per_m"], 200);
    EXPECT_EQ(stiff["integrator_requested"], "implicit");
    EXPECT_EQ(stiff["solver"]["threads"], 3) << "the report says how many threads shared the solve";
    EXPECT_LT(stiff["max_displacement_m"].get<double>(), 0.6 * soft["max_displacement_m"].get<double>());
    const CliResult unknown = run("run --trajectory " + press + " --set material.mass_kg=1 --set material.mass=2");
    EXPECT_EQ(unknown.exitCode, 1);
    EXPECT_NE(unknown.err.find("<settings>:2: material.mass: unknown key"), std::string::npos) << unknown.err;
    const CliResult malformed = run("run --set material");
    EXPECT_EQ(malformed.exitCode, 2);
    EXPECT_NE(malformed.err.find("--set 'material': expected KEY=VALUE"), std::string::npos) << malformed.err;
}

TEST_F(Cli, ASceneReproducesAnExperimentAndTheCommandLineOverridesIt) {
    const std::string scene = std::string(HAPTICUT_SOURCE_DIR) + "/assets/scenes/press-front.toml";
    ASSERT_EQ(run("run --scene " + scene + " --triangles 1619 --force-log " + path("a.csv")).exitCode, 0);
    ASSERT_EQ(run("run --scene " + scene + " --triangles 1619 --force-log " + path("b.csv")).exitCode, 0);
    EXPECT_EQ(slurp(path("a.csv")), slurp(path("b.csv"))) << "the same scene gives the same force log, bit for bit";
    const CliResult r =
        run("run --scene " + scene + " --triangles 1619 --integrator midpoint --report " + path("r.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(path("r.json")));
    EXPECT_EQ(j["integrator"], "midpoint");
    EXPECT_NEAR(j["faces"].get<double>(), 1619, 0.02 * 1619);
    EXPECT_NE(j["trajectory"].get<std::string>().find("press-front.csv"), std::string::npos) << "from the scene";
    std::ofstream(path("bad.toml")) << "[device]\nbackend = \"joystick\"\n";
    const CliResult bad = run("run --scene " + path("bad.toml"));
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("bad.toml:2: device.backend: 'joystick' is not allowed; allowed: replay, virtual"),
              std::string::npos)
        << bad.err;
}

// The shipped liver and kidney scenes run as written: the scalpel opens the liver and walls the wound,
// the probe presses the kidney, and the second part of each, a piece of its own, is left alone.
TEST_F(Cli, TheShippedLiverIsCutAndTheKidneyPressedWithTheirNeighboursLeftAlone) {
    const std::string scenes = std::string(HAPTICUT_SOURCE_DIR) + "/assets/scenes/";
    CliResult r = run("run --scene " + scenes + "liver.toml --report " + path("liver.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto j = nlohmann::json::parse(slurp(path("liver.json")));
    EXPECT_EQ(j["tool"], "scalpel");
    EXPECT_EQ(j["cuts"], 1);
    EXPECT_GT(j["cut_length_m"].get<double>(), 0.03) << "most of the 4 cm stroke";
    EXPECT_EQ(j["boundary_edges"], 0) << "the wound is walled";
    EXPECT_EQ(j["invariants_ok"], true);
    ASSERT_EQ(j["parts"].size(), 2u);
    EXPECT_GT(j["parts"][0]["faces"].get<int>(), j["parts"][0]["faces_at_start"].get<int>()) << "the liver was cut";
    EXPECT_EQ(j["parts"][1]["faces"], j["parts"][1]["faces_at_start"]) << "the gallbladder was not";

    r = run("run --scene " + scenes + "kidney.toml --report " + path("kidney.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(slurp(path("kidney.json")));
    EXPECT_EQ(j["tool"], "probe");
    EXPECT_EQ(j["cuts"], 0);
    EXPECT_GT(j["max_force_N"].get<double>(), 0.5) << "the press is felt";
    EXPECT_GT(j["max_displacement_m"].get<double>(), 1e-3);
    ASSERT_EQ(j["parts"].size(), 2u);
    EXPECT_EQ(j["parts"][1]["name"], "adrenal gland");
    EXPECT_EQ(j["parts"][1]["max_displacement_m"].get<double>(), 0.0) << "nothing joins it to the kidney";
}

TEST_F(Cli, AScalpelStrokeCutsTheHeartWithWallsThatTheExportedMeshKeepsAndAProbeDoesNot) {
    const std::string trajectory = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/cut-front.csv";
    const CliResult r = run("run --trajectory " + trajectory + " --tool scalpel --report " + path("cut.json") +
                            " --export-mesh " + path("cut.obj"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(path("cut.json")));
    for (const char* key :
         {"cut_points", "vertices_added", "faces_added", "cut_length_m", "opened", "invariants_ok", "cut_event_us",
          "boundary_edges", "min_angle_deg", "shortest_edge_m", "tool_threshold_N", "wounds_crossed", "joins"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["opened"], true);
    EXPECT_EQ(j["invariants_ok"], true) << j["invariant_problems"];
    EXPECT_GT(j["cut_length_m"].get<double>(), 0.02);
    EXPECT_GT(j["min_angle_deg"].get<double>(), 5.0);
    // Walls close the wound: the exported heart is still closed, with the walls' faces in it, and the
    // proxy's penetration was measured in every step, through the cut too.
    EXPECT_GT(j["walls_closed"].get<int>(), 5);
    EXPECT_EQ(j["walls_closed"], j["openings"]);
    EXPECT_EQ(j["wall_faces"], 4 * j["walls_closed"].get<int>());
    EXPECT_EQ(j["penetration_measured_steps"], j["steps"]);
    EXPECT_TRUE(j["haptic_rate_hz"].is_null()) << "simulated time has no haptic rate, only a speed";
    EXPECT_GT(j["steps_per_wall_s"].get<double>(), 0.0);
    EXPECT_TRUE(j["period_error_us"].is_null());
    // The blade felt the tissue all through the cut: toughness x depth, and never nothing.
    EXPECT_GT(j["cutting_steps"].get<int>(), 200);
    EXPECT_NEAR(j["cutting_force_N"]["p50"].get<double>(), 2.0, 0.5);
    EXPECT_GT(j["cutting_force_min_N"].get<double>(), 0.1);
    EXPECT_LT(j["max_proxy_penetration_m"].get<double>(), 1e-4);
    EXPECT_GE(j["proxy_push_outs"].get<long>(), 0);
    EXPECT_LT(j["proxy_deepest_push_out_m"].get<double>(), 0.05) << "within the blade's reach of the surface";
    const auto info = nlohmann::json::parse(run("info " + path("cut.obj") + " --json").out);
    EXPECT_EQ(info["closed"], true);
    EXPECT_EQ(info["boundary_edges"], 0);
    EXPECT_EQ(info["faces"], j["faces"]);
    EXPECT_EQ(info["manifold"], true);

    ASSERT_EQ(run("run --trajectory " + trajectory + " --tool probe --report " + path("probe.json")).exitCode, 0);
    const auto probe = nlohmann::json::parse(slurp(path("probe.json")));
    EXPECT_EQ(probe["cut_points"], 0);
    EXPECT_EQ(probe["boundary_edges"], 0);
    EXPECT_EQ(probe["faces"], nlohmann::json::parse(run("info heart --json").out)["faces"]);
    EXPECT_EQ(run("run --trajectory " + trajectory + " --tool chisel").exitCode, 2);
}

// A model with a defect of its own (two faces turned against their neighbours, as an unrepaired import
// has): the load says so, a probe that never cut reports it as the model's and not a cut's, and a
// scalpel's cuts are judged by what they broke beyond it. Repaired, nothing is left to report.
TEST_F(Cli, AModelsOwnDefectsAreReportedAtLoadAndNeverBlamedOnACut) {
    ASSERT_EQ(run("convert heart " + path("heart.obj")).exitCode, 0);
    std::string obj = slurp(path("heart.obj")), turned;
    std::istringstream lines(obj);
    int faces = 0;
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("f ", 0) == 0 && (++faces == 40 || faces == 900)) {
            std::istringstream corners(line.substr(2));
            std::string a, b, c;
            corners >> a >> b >> c;
            line = "f " + a + " " + c + " " + b;
        }
        turned += line + "\n";
    }
    std::ofstream(path("turned.obj")) << turned;
    const std::string trajectory = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/cut-front.csv";

    const CliResult probe = run("run --model " + path("turned.obj") + " --trajectory " + trajectory +
                                " --tool probe --report " + path("probe.json"));
    ASSERT_EQ(probe.exitCode, 0) << probe.err;
    EXPECT_NE(probe.err.find("inconsistently oriented faces"), std::string::npos) << probe.err;
    EXPECT_EQ(probe.out.find("broke the organ"), std::string::npos) << probe.out;
    EXPECT_NE(probe.out.find("defects before the run (not from cutting"), std::string::npos) << probe.out;
    const auto p = nlohmann::json::parse(slurp(path("probe.json")));
    EXPECT_EQ(p["invariants_ok"], true) << p["invariant_problems"];
    ASSERT_FALSE(p["defects_at_load"].empty());
    EXPECT_NE(p["defects_at_load"][0].get<std::string>().find("disagree in orientation"), std::string::npos);

    const CliResult cut = run("run --model " + path("turned.obj") + " --trajectory " + trajectory +
                              " --tool scalpel --report " + path("cut.json"));
    ASSERT_EQ(cut.exitCode, 0) << cut.err;
    const auto c = nlohmann::json::parse(slurp(path("cut.json")));
    EXPECT_GT(c["cut_points"].get<int>(), 0);
    EXPECT_EQ(c["invariants_ok"], true) << c["invariant_problems"];
    EXPECT_EQ(c["defects_at_load"], p["defects_at_load"]);

    ASSERT_EQ(run("convert " + path("turned.obj") + " " + path("repaired.obj") + " --repair").exitCode, 0);
    const CliResult repaired = run("run --model " + path("repaired.obj") + " --trajectory " + trajectory +
                                   " --tool probe --report " + path("repaired.json"));
    ASSERT_EQ(repaired.exitCode, 0) << repaired.err;
    EXPECT_EQ(repaired.err.find("inconsistently oriented"), std::string::npos) << repaired.err;
    EXPECT_TRUE(nlohmann::json::parse(slurp(path("repaired.json")))["defects_at_load"].empty());
}

// A segmentation in body coordinates: millimetres, half a metre from the origin. Loading it says where
// it is and what moves it; --center puts it where the trajectories press, on every command and in a
// scene; --fit-size scales it to a size.
TEST_F(Cli, AModelInBodyCoordinatesIsCentredAndFittedOnEveryCommandAndInScenes) {
    ASSERT_EQ(run("convert heart " + path("heart.obj")).exitCode, 0);
    std::istringstream lines(slurp(path("heart.obj")));
    std::string body;
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("v ", 0) == 0) {
            std::istringstream xyz(line.substr(2));
            double x, y, z;
            xyz >> x >> y >> z;
            line = "v " + std::to_string(1000 * x + 310) + " " + std::to_string(1000 * y - 420) + " " +
                   std::to_string(1000 * z + 180);
        }
        body += line + "\n";
    }
    std::ofstream(path("body.obj")) << body;
    const std::string press = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/press-front.csv";

    const CliResult far =
        run("run --model " + path("body.obj") + " --units mm --trajectory " + press + " --report " + path("far.json"));
    ASSERT_EQ(far.exitCode, 0) << far.err;
    EXPECT_NE(far.err.find("from the origin, where tools, the mouse and trajectories begin; --center"),
              std::string::npos)
        << far.err;
    EXPECT_EQ(nlohmann::json::parse(slurp(path("far.json")))["max_force_N"], 0.0) << "the press met nothing";

    const CliResult centred = run("run --model " + path("body.obj") + " --units mm --center --trajectory " + press +
                                  " --report " + path("centred.json"));
    ASSERT_EQ(centred.exitCode, 0) << centred.err;
    EXPECT_EQ(centred.err.find("from the origin"), std::string::npos) << centred.err;
    const double felt = nlohmann::json::parse(slurp(path("centred.json")))["max_force_N"].get<double>();
    EXPECT_GT(felt, 0.5);

    std::ofstream(path("body.toml")) << "[model]\nsource = \"body.obj\"\nscale = 0.001\ncenter = true\n";
    ASSERT_EQ(
        run("run --scene " + path("body.toml") + " --trajectory " + press + " --report " + path("scene.json")).exitCode,
        0);
    EXPECT_DOUBLE_EQ(nlohmann::json::parse(slurp(path("scene.json")))["max_force_N"].get<double>(), felt);

    const CliResult fitted =
        run("convert " + path("body.obj") + " " + path("fitted.obj") + " --units mm --center --fit-size 0.1");
    ASSERT_EQ(fitted.exitCode, 0) << fitted.err;
    const auto info = nlohmann::json::parse(run("info " + path("fitted.obj") + " --json").out);
    const hapticut::Vec3 lo(info["bbox_min"][0], info["bbox_min"][1], info["bbox_min"][2]);
    const hapticut::Vec3 hi(info["bbox_max"][0], info["bbox_max"][1], info["bbox_max"][2]);
    EXPECT_NEAR((hi - lo).maxCoeff(), 0.1, 1e-6);
    EXPECT_LT(((hi + lo) / 2).norm(), 1e-6);
    EXPECT_EQ(run("run --fit-size 0").exitCode, 2) << "a size must be positive";
}

// A model of named parts (OBJ objects here; glTF and FBX meshes the same): info lists them, --part and
// a scene's [model] parts choose some, and a run presses and cuts each as a piece of its own, reported
// and exported part by part.
TEST_F(Cli, NamedPartsAreListedChosenAndSimulatedAsSeparatePieces) {
    ASSERT_EQ(run("convert heart " + path("heart.obj")).exitCode, 0);
    // The heart twice, the second 0.2 m to the side: two objects of one file.
    std::istringstream lines(slurp(path("heart.obj")));
    std::vector<hapticut::Vec3> vertices;
    std::vector<std::array<int, 3>> faces;
    for (std::string line; std::getline(lines, line);) {
        std::istringstream in(line.substr(std::min<std::size_t>(2, line.size())));
        if (line.rfind("v ", 0) == 0) {
            hapticut::Vec3 p;
            in >> p.x() >> p.y() >> p.z();
            vertices.push_back(p);
        } else if (line.rfind("f ", 0) == 0) {
            std::array<int, 3> f{};
            for (int& c : f) {
                std::string corner;
                in >> corner;
                c = std::stoi(corner.substr(0, corner.find('/')));
            }
            faces.push_back(f);
        }
    }
    std::ostringstream two;
    two << std::setprecision(17);
    for (const double dx : {0.0, 0.2})
        for (const hapticut::Vec3& p : vertices) two << "v " << p.x() + dx << " " << p.y() << " " << p.z() << "\n";
    for (const auto& [name, offset] :
         {std::pair{"ventricle", 0}, std::pair{"atrium", static_cast<int>(vertices.size())}}) {
        two << "o " << name << "\n";
        for (const auto& f : faces)
            two << "f " << f[0] + offset << " " << f[1] + offset << " " << f[2] + offset << "\n";
    }
    std::ofstream(path("two.obj")) << two.str();

    const auto info = nlohmann::json::parse(run("info " + path("two.obj") + " --json").out);
    ASSERT_EQ(info["parts"].size(), 2u) << info.dump();
    EXPECT_EQ(info["parts"][0]["name"], "ventricle");
    EXPECT_EQ(info["parts"][1]["name"], "atrium");
    for (const auto& part : info["parts"]) EXPECT_EQ(part["closed"], true);
    const int perPart = info["parts"][0]["faces"].get<int>();
    EXPECT_EQ(info["faces"].get<int>(), 2 * perPart);

    const auto one = nlohmann::json::parse(run("info " + path("two.obj") + " --part atrium --json").out);
    EXPECT_EQ(one["faces"].get<int>(), perPart);
    EXPECT_TRUE(one["parts"].empty()) << "one part left is a model of one part";
    const CliResult unknown = run("info " + path("two.obj") + " --part valve");
    EXPECT_NE(unknown.exitCode, 0);
    EXPECT_NE(unknown.err.find("no part named 'valve': the model's parts are 'ventricle' and 'atrium'"),
              std::string::npos)
        << unknown.err;

    const std::string cut = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/cut-front.csv";
    const CliResult r = run("run --model " + path("two.obj") + " --trajectory " + cut + " --tool scalpel --report " +
                            path("r.json") + " --export-mesh " + path("cut.obj"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(path("r.json")));
    EXPECT_EQ(j["invariants_ok"], true) << j["invariant_problems"];
    ASSERT_EQ(j["parts"].size(), 2u);
    const auto& ventricle = j["parts"][0];
    const auto& atrium = j["parts"][1];
    EXPECT_GT(ventricle["faces"].get<int>(), ventricle["faces_at_start"].get<int>()) << "the blade cut it";
    EXPECT_GT(ventricle["max_displacement_m"].get<double>(), 1e-4);
    EXPECT_EQ(atrium["faces"], atrium["faces_at_start"]) << "a piece of its own, 0.2 m away";
    EXPECT_LT(atrium["max_displacement_m"].get<double>(), 1e-9) << "nothing joins it to the cut part";
    const std::string exported = slurp(path("cut.obj"));
    EXPECT_NE(exported.find("o ventricle\n"), std::string::npos);
    EXPECT_NE(exported.find("o atrium\n"), std::string::npos);
    const auto after = nlohmann::json::parse(run("info " + path("cut.obj") + " --json").out);
    ASSERT_EQ(after["parts"].size(), 2u);
    EXPECT_EQ(after["parts"][0]["faces"], ventricle["faces"]);
    EXPECT_EQ(after["parts"][0]["closed"], true) << "the cut's walls are the ventricle's";

    std::ofstream(path("atrium.toml")) << "[model]\nsource = \"two.obj\"\nparts = [\"atrium\"]\n";
    ASSERT_EQ(run("run --scene " + path("atrium.toml") + " --steps 10 --report " + path("s.json")).exitCode, 0);
    EXPECT_EQ(nlohmann::json::parse(slurp(path("s.json")))["faces"].get<int>(), perPart);
}

// An empty result is an error, not a file: a weld as large as the model, coordinates so large that the
// default weld tolerance once overflowed and joined every vertex, a model without faces.
TEST_F(Cli, EmptyResultsAreErrorsAndModelsWithoutFacesAreRefused) {
    const CliResult welded = run("convert heart " + path("x.txt") + " --weld 1");
    EXPECT_EQ(welded.exitCode, 1);
    EXPECT_NE(welded.err.find("nothing left to write: a weld of 1 m"), std::string::npos) << welded.err;
    EXPECT_FALSE(fs::exists(path("x.txt")));

    std::ofstream(path("huge.obj")) << "v 0 0 0\nv 1e200 0 0\nv 0 1e200 0\nv 0 0 1e200\n"
                                       "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    const CliResult huge = run("convert " + path("huge.obj") + " " + path("huge.ply") + " --repair");
    EXPECT_EQ(huge.exitCode, 0) << huge.err;
    EXPECT_NE(huge.out.find("4 vertices, 4 faces"), std::string::npos) << huge.out;

    std::ofstream(path("empty.txt")) << "physics\n0.3 0.18 0.0002 90766 123\nvertices 1\n0 0 0\nfaces 0\nnormals "
                                        "0\nedges 0\n";
    for (const std::string& command :
         {"run --model " + path("empty.txt"), "soak --strokes 2 --model " + path("empty.txt"),
          "run --model " + path("empty.txt") + " --trajectory " + std::string(HAPTICUT_SOURCE_DIR) +
              "/assets/trajectories/press-front.csv"}) {
        const CliResult empty = run(command);
        EXPECT_EQ(empty.exitCode, 1) << command;
        EXPECT_NE(empty.err.find("the model has no faces"), std::string::npos) << command << ": " << empty.err;
    }
}

// Real-time runs longer than a second, with the progress line, the step log's ring and its writer all
// running beside the loop's thread (ThreadSanitizer watches this in CI): a replayed scalpel and the
// emulated Touch.
TEST_F(Cli, RealTimeRunsLongerThanASecondLogEveryStepWhileTheProgressLineRuns) {
    // Real time, not simulated time (which runs many times faster and reports no rate): the loop keeps
    // near the servo's 1 kHz. Under a sanitizer, with a test beside it, a step can outlast the servo's
    // millisecond (ThreadSanitizer once held the emulated Touch to 474 Hz).
#ifdef HAPTICUT_SANITIZED
    constexpr double kLeastRate_hz = 250;
#else
    constexpr double kLeastRate_hz = 500;
#endif
    const std::string trajectory = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/cut-front.csv";
    const std::string env = std::string("HAPTICUT_HD_LIBRARY=") + HD_EMULATION_LIBRARY + " ";
    for (const std::string& device : {"--trajectory " + trajectory, std::string("--device openhaptics")}) {
        SCOPED_TRACE(device);
        const CliResult r =
            run_with_env(env, "run " + device + " --tool scalpel --realtime --steps 1500 --force-log " + path("f.csv") +
                                  " --record " + path("rec.csv") + " --report " + path("rt.json"));
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const auto j = nlohmann::json::parse(slurp(path("rt.json")));
        EXPECT_EQ(j["steps"], 1500);
        EXPECT_GT(j["haptic_rate_hz"].get<double>(), kLeastRate_hz);
        ASSERT_TRUE(j["physics_step_us"].is_object()) << "how long the physics' steps took";
        EXPECT_GT(j["physics_step_us"]["max"].get<double>(), 0.0);
        // Single-rate a slow step is an overrun; a run a sanitizer slows into multi-rate says what it lost.
        if (j["multi_rate"] == true) {
            EXPECT_GE(j["physics_time_lost_s"].get<double>(), 0.0);
        } else {
            EXPECT_TRUE(j["physics_time_lost_s"].is_null()) << "single-rate: a step that overruns is an overrun";
        }
        const std::string log = slurp(path("f.csv"));
        EXPECT_EQ(std::count(log.begin(), log.end(), '\n') - 1 + j["log_dropped_steps"].get<long>(), 1500);
        if (j["log_dropped_steps"] == 0) {
            EXPECT_NE(r.out.find("wrote 1500 steps to"), std::string::npos) << r.out;
        }
    }
}

// An organ exported inside out (every face's normal into the tissue, as some exporters write them)
// loads outward with a warning, and is pressed as the heart is: inside out, the probe's proxy sank
// millimetres into the tissue and the dent stayed after the probe left.
TEST_F(Cli, AnOrganExportedInsideOutIsTurnedOutwardAndPressedAsItShouldBe) {
    ASSERT_EQ(run("convert heart " + path("heart.obj")).exitCode, 0);
    std::istringstream in(slurp(path("heart.obj")));
    std::ofstream out(path("inside-out.obj"));
    for (std::string line; std::getline(in, line);) {
        std::istringstream words(line);
        std::string tag, a, b, c;
        if (words >> tag >> a >> b >> c && tag == "f")
            out << "f " << a << " " << c << " " << b << "\n";
        else
            out << line << "\n";
    }
    out.close();
    const std::string press = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/press-front.csv";
    auto pressed = [&](const std::string& model, const std::string& report) {
        const CliResult r = run("run --model " + path(model) + " --trajectory " + press + " --report " + path(report));
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return std::pair{r, nlohmann::json::parse(slurp(path(report)))};
    };
    const auto [turned, j] = pressed("inside-out.obj", "turned.json");
    EXPECT_NE(turned.err.find("1 piece came inside out (1616 faces"), std::string::npos) << turned.err;
    const auto [plain, expected] = pressed("heart.obj", "plain.json");
    EXPECT_EQ(plain.err.find("inside out"), std::string::npos) << plain.err;
    EXPECT_LT(j["max_proxy_penetration_m"].get<double>(), 1e-4);
    EXPECT_NEAR(j["max_force_N"].get<double>(), expected["max_force_N"].get<double>(), 1e-6);
    EXPECT_LT(j["final_max_displacement_m"].get<double>(), 1e-3) << "the tissue springs back";
}

// A multi-rate run says where its tissue fell short of real time: steps longer than the longest step
// lose wall time, and at the end the tissue is about a step behind.
TEST_F(Cli, AMultiRateRunSaysWhereItsTissueFellShortOfRealTime) {
    const std::string press = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/press-front.csv";
    const CliResult r =
        run("run --trajectory " + press + " --realtime --steps 400 --set simulation.physics_rate=multi" + " --report " +
            path("mr.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(path("mr.json")));
    ASSERT_EQ(j["multi_rate"], true);
    ASSERT_TRUE(j["physics_step_us"].is_object());
    EXPECT_GT(j["physics_step_us"]["mean"].get<double>(), 0.0);
    const double wall = j["wall_time_s"], factor = j["physics_realtime_factor"];
    const double lost = j["physics_time_lost_s"], lag = j["physics_lag_at_end_s"];
    EXPECT_GE(lost, 0.0);
    EXPECT_GE(lag, 0.0);
    EXPECT_LT(lag, 0.2) << "a step of the 1,619 heart or two";
    if (lag > 0) {
        EXPECT_NEAR(wall * factor + lost + lag, wall, 1e-6) << "the shortfall is the two";
    }
    EXPECT_NE(r.out.find("behind the wall clock at the end"), std::string::npos) << r.out;
}

// A material so stiff that RK4 would need tens of thousands of substeps a step: refused up front with
// the way out, instead of a run that crawls for hours (one such ran 14 minutes without a word).
// A large organ's build and preparation each say so as they start, in order, before the run's summary,
// so a log of a million-triangle run (15 s and 8 s of them) is never silent; a small one's run is not
// cluttered with them.
TEST_F(Cli, ALargeOrgansSlowPhasesEachSayWhenTheyStart) {
    const std::string press = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/press-front.csv";
    const CliResult large = run("run --triangles 200000 --steps 5 --trajectory " + press);
    ASSERT_EQ(large.exitCode, 0) << large.err;
    const auto building = large.err.find("building the heart of 200000 triangles");
    const auto preparing = large.err.find("preparing the collision tree and the integrator for");
    ASSERT_NE(building, std::string::npos) << large.err;
    ASSERT_NE(preparing, std::string::npos) << large.err;
    EXPECT_LT(building, preparing);
    const CliResult small = run("run --steps 5 --trajectory " + press);
    ASSERT_EQ(small.exitCode, 0) << small.err;
    EXPECT_EQ(small.err.find("building the heart"), std::string::npos) << small.err;
    EXPECT_EQ(small.err.find("preparing the collision tree"), std::string::npos) << small.err;
}

TEST_F(Cli, AnExplicitRunThatWouldCrawlIsRefusedWithTheWayOut) {
    std::ofstream(path("stiff.toml"))
        << "[material]\nstructural_stiffness_N = 1e9\n[simulation]\nintegrator = \"rk4\"\n";
    const CliResult headless = run("run --scene " + path("stiff.toml") + " --steps 10");
    EXPECT_EQ(headless.exitCode, 2);
    const CliResult haptic = run("run --scene " + path("stiff.toml") + " --trajectory " +
                                 std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/press-front.csv");
    EXPECT_EQ(haptic.exitCode, 1);
    for (const CliResult& r : {headless, haptic}) {
        EXPECT_NE(r.err.find("rk4 would need"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("more than the 10000 allowed"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("--integrator implicit"), std::string::npos) << r.err;
    }
    EXPECT_EQ(run("run --scene " + path("stiff.toml") + " --integrator auto --steps 10").exitCode, 0)
        << "auto takes the implicit scheme instead";
}

TEST_F(Cli, ExportsTheDeformedMesh) {
    const CliResult r = run("run --steps 100 --force-at 0,0,0.05 --force 0,0,-1 --export-mesh " + path("pressed.ply"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(run("info " + path("pressed.ply") + " --json").out);
    EXPECT_EQ(j["closed"], true);
    EXPECT_LT(j["bbox_max"][2].get<double>(),
              nlohmann::json::parse(run("info heart --json").out)["bbox_max"][2].get<double>() + 1e-9);
}

}  // namespace

namespace {

// The shipped exercises with their sample sessions: an incision along the line and one beside it, and a
// palpation that finds the lump; the same report twice; and what cannot be assessed, said clearly.
TEST_F(Cli, AssessScoresTheShippedExercisesSampleSessions) {
    const std::string assets = std::string(HAPTICUT_SOURCE_DIR) + "/assets/";
    const auto assess = [&](const std::string& scene, const std::string& session, const std::string& report) {
        return run("assess --scene " + assets + "scenes/" + scene + " --session " + assets + "sessions/" + session +
                   " --report " + path(report));
    };
    const CliResult along = assess("incision-front.toml", "incision-front.csv", "along.json");
    ASSERT_EQ(along.exitCode, 0) << along.err;
    EXPECT_NE(along.out.find("incision: score"), std::string::npos) << along.out;
    const auto j = nlohmann::json::parse(slurp(path("along.json")));
    for (const char* key :
         {"score", "parts", "deviation_rms_mm", "deviation_max_mm", "coverage_pct", "outside_corridor_mm",
          "max_force_N", "mean_force_N", "duration_s", "strokes", "figure", "exercise"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_LT(j["deviation_rms_mm"].get<double>(), 1.0);
    EXPECT_GT(j["coverage_pct"].get<double>(), 90);
    EXPECT_GT(j["score"].get<double>(), 85);
    EXPECT_EQ(j["parts"].size(), 5u);
    EXPECT_EQ(j["exercise"]["corridor_mm"], 3.0) << "the thresholds the parts are judged against";
    ASSERT_EQ(assess("incision-front.toml", "incision-front.csv", "again.json").exitCode, 0);
    auto again = nlohmann::json::parse(slurp(path("again.json")));
    auto first = j;
    first.erase("provenance"), again.erase("provenance");
    EXPECT_EQ(first, again) << "the same session, the same report";

    const CliResult aside = assess("incision-front.toml", "incision-front-aside.csv", "aside.json");
    ASSERT_EQ(aside.exitCode, 0) << aside.err;
    const auto a = nlohmann::json::parse(slurp(path("aside.json")));
    EXPECT_GT(a["deviation_rms_mm"].get<double>(), 3);
    EXPECT_LT(a["coverage_pct"].get<double>(), 20);
    EXPECT_LT(a["score"].get<double>(), 20);

    const CliResult palpation = assess("palpation-lump.toml", "palpation-lump.csv", "lump.json");
    ASSERT_EQ(palpation.exitCode, 0) << palpation.err;
    const auto p = nlohmann::json::parse(slurp(path("lump.json")));
    EXPECT_EQ(p["found"], 1);
    EXPECT_EQ(p["marks"], 1);
    EXPECT_LT(p["localisation_error_mm"].get<double>(), 8);
    EXPECT_GT(p["score"].get<double>(), 70);

    const CliResult none =
        run("assess --scene " + assets + "scenes/heart.toml --session " + assets + "sessions/incision-front.csv");
    EXPECT_EQ(none.exitCode, 2);
    EXPECT_NE(none.err.find("the scene has no [exercise]"), std::string::npos) << none.err;
    std::ofstream(path("bad.csv")) << "t,x,y,z,button\n0,0,0,0,0\n0.1,0,0,0,5\n";
    const CliResult bad = run("assess --scene " + assets + "scenes/incision-front.toml --session " + path("bad.csv") +
                              " --report " + path("b.json"));
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("bad.csv:3: button must be"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(path("b.json")));
    EXPECT_EQ(run("assess --scene " + assets + "scenes/incision-front.toml").exitCode, 2) << "--session is required";
}

TEST_F(Cli, SoakCutsWithRandomStrokesAndReportsTheInvariants) {
    const CliResult r = run("soak --strokes 60 --per-organ 30 --seed 9 --report " + path("soak.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(path("soak.json")));
    EXPECT_EQ(j["strokes"], 60);
    EXPECT_EQ(j["organs"], 2);
    EXPECT_EQ(j["seed"], 9);
    EXPECT_EQ(j["invariants_ok"], true);
    EXPECT_GT(j["cut_points"].get<long>(), 60);
    EXPECT_GT(j["invariant_checks"].get<long>(), 60);
    EXPECT_NE(r.out.find("all held"), std::string::npos) << r.out;
    // A model that cannot load: a clear message and a failure, no report.
    const CliResult bad = run("soak --model " + path("missing.obj") + " --report " + path("bad.json"));
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("missing.obj"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(path("bad.json")));
}

}  // namespace

namespace {

TEST_F(Cli, DevicesListsEveryBackendAndWhyOneIsMissing) {
    const CliResult r = run("devices --json --hd-library libHD-not-installed.so");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j.size(), 4u);
    std::map<std::string, nlohmann::json> byName;
    for (const auto& b : j) byName[b["backend"]] = b;
    EXPECT_EQ(byName["virtual"]["available"], true);
    EXPECT_EQ(byName["replay"]["available"], true);
    EXPECT_EQ(byName["openhaptics"]["available"], false);
    EXPECT_NE(byName["openhaptics"]["detail"].get<std::string>().find("libHD-not-installed.so"), std::string::npos);
    EXPECT_FALSE(byName["sdl"]["detail"].get<std::string>().empty()) << "the joysticks SDL sees, or why none";
    EXPECT_TRUE(byName["sdl"]["joysticks"].is_array());
    // With the HD API's emulation in its place, OpenHaptics is available through that library.
    const CliResult found = run("devices --json --hd-library " + std::string(HD_EMULATION_LIBRARY));
    ASSERT_EQ(found.exitCode, 0) << found.err;
    for (const auto& b : nlohmann::json::parse(found.out)) {
        if (b["backend"] == "openhaptics") {
            EXPECT_EQ(b["available"], true) << b.dump();
        }
    }
}

TEST_F(Cli, ASceneDescribesEachHandsDeviceAndTheCommandLineOverridesIt) {
    const std::string scene = std::string(HAPTICUT_SOURCE_DIR) + "/assets/scenes/two-hands.toml";
    const CliResult r = run("run --scene " + scene + " --report " + path("scene.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(path("scene.json")));
    ASSERT_EQ(j["hands"].size(), 2u);
    EXPECT_EQ(j["hands"][0]["tool"], "scalpel") << "each [[devices]] entry brings its tool";
    EXPECT_EQ(j["hands"][1]["tool"], "probe");
    EXPECT_NE(j["hands"][0]["device"].get<std::string>().find("cut-front.csv"), std::string::npos);
    EXPECT_GT(j["cut_points"].get<int>(), 5) << "the scalpel in the first hand cut";
    EXPECT_LE(j["hands"][1]["max_force_N"].get<double>(), 2.0 + 1e-9) << "the second device's own force limit";
    EXPECT_GT(j["hands"][1]["max_force_N"].get<double>(), 0.5);

    const std::string trajectories = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/";
    const CliResult cli =
        run("run --scene " + scene + " --trajectory " + trajectories + "press-front.csv --report " + path("cli.json"));
    ASSERT_EQ(cli.exitCode, 0) << cli.err;
    const auto k = nlohmann::json::parse(slurp(path("cli.json")));
    ASSERT_EQ(k["hands"].size(), 1u) << "devices on the command line replace the scene's";
    EXPECT_EQ(k["hands"][0]["tool"], "probe");
    const CliResult tool = run("run --scene " + scene + " --tool probe --report " + path("tool.json"));
    ASSERT_EQ(tool.exitCode, 0) << tool.err;
    EXPECT_EQ(nlohmann::json::parse(slurp(path("tool.json")))["hands"][0]["tool"], "probe")
        << "--tool overrides the first hand's";
}

TEST_F(Cli, RunTakesADevicePerHandAndReportsEachHand) {
    const std::string trajectories = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/";
    const CliResult r =
        run("run --trajectory " + trajectories + "cut-front.csv --tool scalpel --device replay:" + trajectories +
            "press-front.csv --force-log " + path("log.csv") + " --report " + path("two.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(path("two.json")));
    ASSERT_EQ(j["hands"].size(), 2u);
    EXPECT_EQ(j["hands"][0]["tool"], "scalpel");
    EXPECT_EQ(j["hands"][1]["tool"], "probe");
    EXPECT_EQ(j["hands"][1]["device"], "replay:" + trajectories + "press-front.csv");
    EXPECT_GT(j["hands"][1]["max_force_N"].get<double>(), 0.5) << "the second hand pressed";
    EXPECT_GT(j["hands"][1]["contact_steps"].get<long>(), 100);
    EXPECT_GT(j["cut_points"].get<int>(), 5) << "the first hand's scalpel cut";
    const std::string log = slurp(path("log.csv"));
    EXPECT_NE(log.substr(0, log.find('\n')).find(",fx2,fy2,fz2,contact2,face2"), std::string::npos)
        << "the log has both hands";

    const CliResult bad = run("run --device phantom");
    EXPECT_EQ(bad.exitCode, 2);
    EXPECT_NE(bad.err.find("expected virtual, replay:FILE, openhaptics[:NAME] or sdl[:INDEX]"), std::string::npos)
        << bad.err;
    const CliResult three =
        run("run --trajectory " + trajectories + "cut-front.csv --device replay:a.csv --device replay:b.csv");
    EXPECT_EQ(three.exitCode, 2);
    EXPECT_NE(three.err.find("at most 2"), std::string::npos) << three.err;
    const CliResult missing = run("run --device replay:" + path("nowhere.csv"));
    EXPECT_EQ(missing.exitCode, 1);
    EXPECT_NE(missing.err.find("nowhere.csv"), std::string::npos) << missing.err;
}

TEST_F(Cli, ALiveDeviceRunsInRealTimeAndTheSelfTestChecksItEndToEnd) {
    const std::string env = std::string("HAPTICUT_HD_LIBRARY=") + HD_EMULATION_LIBRARY + " ";
    const CliResult r = run_with_env(env, "run --device openhaptics --steps 300 --report " + path("live.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(path("live.json")));
    EXPECT_EQ(j["realtime"], true) << "a live device runs on the wall clock";
    EXPECT_EQ(j["steps"], 300);
    ASSERT_TRUE(j["period_error_us"].is_object()) << "measured in the mode it ran in, not by --realtime";
    EXPECT_TRUE(j["period_error_us"].contains("p99")) << j["period_error_us"];
    EXPECT_GE(j["overruns"].get<long>(), j["missed_periods"].get<long>()) << "every missed period is an overrun";
    EXPECT_TRUE(j.contains("stalls"));
    EXPECT_NE(j["hands"][0]["description"].get<std::string>().find("workspace fitted to the model"), std::string::npos)
        << j["hands"][0].dump();

    const CliResult ok = run("devices --json --self-test openhaptics --force-pulse --seconds 0.3 --hd-library " +
                             std::string(HD_EMULATION_LIBRARY));
    ASSERT_EQ(ok.exitCode, 0) << ok.out << ok.err;
    const auto report = nlohmann::json::parse(ok.out);
    EXPECT_EQ(report["ok"], true);
    std::map<std::string, nlohmann::json> checks;
    for (const auto& c : report["checks"]) checks[c["check"]] = c;
    EXPECT_EQ(checks["positions"]["ok"], true);
    EXPECT_NE(checks["force"]["detail"].get<std::string>().find("pushed up to 0.50 N"), std::string::npos)
        << checks["force"].dump();

    const CliResult broken =
        run("devices --self-test openhaptics --hd-library " + std::string(HD_EMULATION_INCOMPLETE_LIBRARY));
    EXPECT_EQ(broken.exitCode, 1);
    EXPECT_NE(broken.out.find("open       FAIL"), std::string::npos) << broken.out;
    EXPECT_NE(broken.out.find("lacks"), std::string::npos) << "names what the library is missing: " << broken.out;
}

}  // namespace
