// `hapticut assets --out DIR`: regenerates the shipped models, tools and trajectories from the project's code.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>

#include "commands.h"
#include "hapticut/collision/bvh.h"
#include "hapticut/common/line_reader.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/mesh/io/obj_format.h"
#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/organs.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/sample_trajectories.h"

namespace hapticut::app {

namespace {

/// The exercises' heart: fine enough that a cut follows the blade to a fraction of a millimetre.
constexpr int kExerciseHeartTriangles = 4000;

constexpr std::size_t kLiverTriangles = 8000, kKidneyTriangles = 4000;
const Vec2 kLiverCut(-0.04, 0.0);       // across the front of the right lobe
const Vec2 kKidneyPress(-0.005, 0.01);  // the middle of its front

/// A segmented organ made simulation-ready, written as OBJ with its parts as groups; what it took, told.
WriteStatus writeReadyOrgan(const std::filesystem::path& file, const mesh::SurfaceMesh& segmented,
                            std::size_t triangles, mesh::SurfaceMesh& ready) {
    const mesh::MeshReport before = mesh::validateMesh(segmented);
    auto organ = mesh::procedural::makeSimulationReady(segmented, triangles);
    if (!organ) return Error{file.string(), 0, "cannot make the organ simulation-ready: " + organ.error()};
    const mesh::MeshReport after = mesh::validateMesh(organ->mesh);
    std::cout << file.filename().string() << ": segmented " << before.faces << " faces (smallest angle "
              << threeDigits(before.minAngleDeg) << " deg), repaired and remeshed to " << after.faces
              << " faces (smallest angle " << threeDigits(after.minAngleDeg) << " deg, " << organ->mesh.partNames.size()
              << " parts, " << (after.closed && after.oriented ? "" : "not ") << "closed and oriented), "
              << threeDigits(organ->remesh.distanceMean_m * 1e3) << " mm from the segmentation on average, "
              << threeDigits(organ->remesh.distanceMax_m * 1e3) << " mm at most\n";
    ready = std::move(organ->mesh);
    // A tenth of a micrometre and a millionth of the texture are precision enough; full doubles would
    // triple the files.
    for (Vec3& p : ready.positions) p = (p * 1e7).array().round() / 1e7;
    for (mesh::FaceUvs& face : ready.uvs)
        for (Vec2& uv : face) uv = (uv * 1e6).array().round() / 1e6;
    return writeTextFileAtomically(file, mesh::io::formatObj(ready));
}

int assets(const std::filesystem::path& out) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(out / "models", ec);
    fs::create_directories(out / "tools", ec);
    fs::create_directories(out / "trajectories", ec);
    fs::create_directories(out / "sessions", ec);
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    collision::Bvh bvh;
    bvh.build({heart.positions, heart.faces});
    // The exercises' heart (assets/scenes/incision-front.toml, palpation-lump.toml) and sample sessions
    // of them: an incision along the line, one 4 mm beside it, and a palpation that finds the lump at
    // the third press.
    const mesh::SurfaceMesh exerciseHeart = mesh::procedural::makeHeart({kExerciseHeartTriangles});
    collision::Bvh exerciseBvh;
    exerciseBvh.build({exerciseHeart.positions, exerciseHeart.faces});
    const auto session = [&](const haptics::Trajectory& t) { return haptics::formatTrajectory(t); };
    // The liver and the kidney are segmented from implicit shapes and made ready as a user's would be.
    mesh::SurfaceMesh liver, kidney;
    const WriteStatus liverWritten =
        writeReadyOrgan(out / "models/liver.obj", mesh::procedural::segmentLiver(), kLiverTriangles, liver);
    const WriteStatus kidneyWritten =
        writeReadyOrgan(out / "models/kidney.obj", mesh::procedural::segmentKidney(), kKidneyTriangles, kidney);
    collision::Bvh liverBvh, kidneyBvh;
    liverBvh.build({liver.positions, liver.faces});
    kidneyBvh.build({kidney.positions, kidney.faces});
    const struct {
        fs::path file;
        WriteStatus status;
    } written[] = {
        {out / "models/heart.txt", mesh::io::writeModelFile(out / "models/heart.txt", heart,
                                                            physics::thesisPhysicsFor(heart, physics::Material{}))},
        {out / "models/liver.obj", liverWritten},
        {out / "models/kidney.obj", kidneyWritten},
        {out / "tools/scalpel.txt", mesh::io::writeToolFile(out / "tools/scalpel.txt", mesh::procedural::makeScalpel(),
                                                            mesh::procedural::kScalpelThreshold_N)},
        {out / "tools/probe.txt", mesh::io::writeToolFile(out / "tools/probe.txt", mesh::procedural::makeProbe(),
                                                          mesh::procedural::kProbeThreshold_N)},
        {out / "trajectories/press-front.csv",
         writeTextFileAtomically(out / "trajectories/press-front.csv",
                                 haptics::formatTrajectory(scene::pressTrajectory(heart, bvh)))},
        {out / "trajectories/stroke-front.csv",
         writeTextFileAtomically(out / "trajectories/stroke-front.csv",
                                 haptics::formatTrajectory(scene::strokeTrajectory(heart, bvh, 0.004)))},
        {out / "trajectories/cut-front.csv",
         writeTextFileAtomically(out / "trajectories/cut-front.csv",
                                 haptics::formatTrajectory(scene::strokeTrajectory(heart, bvh, 0.012)))},
        {out / "trajectories/cut-liver.csv",
         writeTextFileAtomically(out / "trajectories/cut-liver.csv", haptics::formatTrajectory(scene::strokeTrajectory(
                                                                         liver, liverBvh, 0.012, kLiverCut)))},
        {out / "trajectories/press-kidney.csv",
         writeTextFileAtomically(out / "trajectories/press-kidney.csv",
                                 haptics::formatTrajectory(scene::pressTrajectory(kidney, kidneyBvh, kKidneyPress)))},
        {out / "sessions/incision-front.csv",
         writeTextFileAtomically(
             out / "sessions/incision-front.csv",
             session(scene::incisionStroke(exerciseHeart, exerciseBvh, -0.01, -0.015, 0.015, 0.01)))},
        {out / "sessions/incision-front-aside.csv",
         writeTextFileAtomically(
             out / "sessions/incision-front-aside.csv",
             session(scene::incisionStroke(exerciseHeart, exerciseBvh, -0.014, -0.015, 0.015, 0.01)))},
        {out / "sessions/palpation-lump.csv",
         writeTextFileAtomically(
             out / "sessions/palpation-lump.csv",
             session(scene::palpationSession(exerciseHeart, exerciseBvh,
                                             {Vec2(-0.012, -0.015), Vec2(0.025, -0.035), Vec2(0.017, -0.023)}, 2)))},
    };
    int status = 0;
    for (const auto& w : written) {
        if (w.status) {
            std::cerr << w.status->toString() << "\n";
            status = 1;
        } else {
            std::cout << "wrote " << w.file.string() << "\n";
        }
    }
    return status;
}

}  // namespace

Command addAssetsCommand(CLI::App& app) {
    auto out = std::make_shared<std::string>("assets");
    CLI::App* cmd = app.add_subcommand(
        "assets",
        "Regenerate the shipped heart (1,619 triangles), liver, kidney, scalpel, probe, sample trajectories and the "
        "exercises' sample sessions");
    cmd->add_option("--out", *out, "Directory to write models/ and tools/ into")->capture_default_str();
    return [out] { return assets(*out); };
}

}  // namespace hapticut::app
