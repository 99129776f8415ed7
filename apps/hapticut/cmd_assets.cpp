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

namespace hapticut::app {

namespace {

/// The front surface of the heart at (x, y): where a ray from +z first meets it.
double frontSurfaceZ(const mesh::SurfaceMesh& heart, const collision::Bvh& bvh, double x, double y) {
    const collision::SurfaceView view{heart.positions, heart.faces};
    const auto hit = bvh.firstHit(view, Vec3(x, y, 0.2), Vec3(x, y, -0.2));
    return hit ? hit->point.z() : 0.0;
}

haptics::TrajectoryPoint at(double t, const Vec3& p, std::uint32_t button = 0) {
    haptics::TrajectoryPoint point;
    point.t_s = t;
    point.sample.position_m = p;
    point.sample.buttons = button;
    return point;
}

/// Press the front of the heart 6 mm deep, hold, release. Free until 0.6 s, after the force ramp.
haptics::Trajectory pressTrajectory(const mesh::SurfaceMesh& heart, const collision::Bvh& bvh) {
    const double z = frontSurfaceZ(heart, bvh, 0.0, -0.01);
    haptics::Trajectory t;
    for (const auto& [time, dz] : {std::pair{0.0, 0.03}, {0.6, 0.005}, {1.0, -0.006}, {1.5, -0.006}, {1.8, 0.03}, {2.5, 0.03}})
        t.points.push_back(at(time, Vec3(0.0, -0.01, z + dz), time >= 0.6 && time <= 1.5));
    return t;
}

/// Press `depth_m` into the front, stroke 4 cm across it following the surface, lift off. 4 mm is a
/// probe's stroke; 12 mm presses with about 2.5 N, past the scalpel's 2 N threshold, so it cuts.
haptics::Trajectory strokeTrajectory(const mesh::SurfaceMesh& heart, const collision::Bvh& bvh, double depth_m) {
    const double y = -0.01, x0 = -0.02, x1 = 0.02, depth = depth_m;
    haptics::Trajectory t;
    t.points.push_back(at(0.0, Vec3(x0, y, frontSurfaceZ(heart, bvh, x0, y) + 0.03)));
    t.points.push_back(at(0.6, Vec3(x0, y, frontSurfaceZ(heart, bvh, x0, y) + 0.003)));
    for (int i = 0; i <= 40; ++i) {  // 4 cm in 1 s, a sample every 25 ms
        const double x = x0 + (x1 - x0) * i / 40.0;
        t.points.push_back(at(0.9 + 0.025 * i, Vec3(x, y, frontSurfaceZ(heart, bvh, x, y) - depth), 1));
    }
    t.points.push_back(at(2.2, Vec3(x1, y, frontSurfaceZ(heart, bvh, x1, y) + 0.03)));
    t.points.push_back(at(2.8, Vec3(x1, y, frontSurfaceZ(heart, bvh, x1, y) + 0.03)));
    return t;
}

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
        mesh::io::WriteStatus status;
    } written[] = {
        {out / "models/heart.txt", mesh::io::writeModelFile(out / "models/heart.txt", heart, physics::thesisPhysicsFor(heart, physics::Material{}))},
        {out / "tools/scalpel.txt", mesh::io::writeToolFile(out / "tools/scalpel.txt", mesh::procedural::makeScalpel(), mesh::procedural::kScalpelThreshold_N)},
        {out / "tools/probe.txt", mesh::io::writeToolFile(out / "tools/probe.txt", mesh::procedural::makeProbe(), mesh::procedural::kProbeThreshold_N)},
        {out / "trajectories/press-front.csv",
         mesh::io::writeTextFileAtomically(out / "trajectories/press-front.csv", haptics::formatTrajectory(pressTrajectory(heart, bvh)))},
        {out / "trajectories/stroke-front.csv",
         mesh::io::writeTextFileAtomically(out / "trajectories/stroke-front.csv", haptics::formatTrajectory(strokeTrajectory(heart, bvh, 0.004)))},
        {out / "trajectories/cut-front.csv",
         mesh::io::writeTextFileAtomically(out / "trajectories/cut-front.csv", haptics::formatTrajectory(strokeTrajectory(heart, bvh, 0.012)))},
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
    CLI::App* cmd = app.add_subcommand("assets", "Regenerate the shipped heart (1,619 triangles), scalpel, probe and sample trajectories");
    cmd->add_option("--out", *out, "Directory to write models/ and tools/ into")->capture_default_str();
    return [out] { return assets(*out); };
}

}  // namespace hapticut::app
