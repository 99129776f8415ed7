// `hapticut assets --out DIR`: regenerates the shipped heart model and tool files from the project's code.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>

#include "commands.h"
#include "hapticut/collision/bvh.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/sample_trajectories.h"

namespace hapticut::app {

namespace {

int assets(const std::filesystem::path& out) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(out / "models", ec);
    fs::create_directories(out / "tools", ec);
    fs::create_directories(out / "trajectories", ec);
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    collision::Bvh bvh;
    bvh.build({heart.positions, heart.faces});
    const struct {
        fs::path file;
        WriteStatus status;
    } written[] = {
        {out / "models/heart.txt", mesh::io::writeModelFile(out / "models/heart.txt", heart,
                                                            physics::thesisPhysicsFor(heart, physics::Material{}))},
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
        "assets", "Regenerate the shipped heart (1,619 triangles), scalpel, probe and sample trajectories");
    cmd->add_option("--out", *out, "Directory to write models/ and tools/ into")->capture_default_str();
    return [out] { return assets(*out); };
}

}  // namespace hapticut::app
