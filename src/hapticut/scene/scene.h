// Scene = organ model + tools + devices + settings (DESIGN "Layers"): the one place a scene is
// assembled, from a scene file or the built-in default, with a command line's overrides applied.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/cutting/cut_model.h"
#include "hapticut/scene/model_source.h"
#include "hapticut/scene/scene_file.h"

namespace hapticut::scene {

/// What a command line (or a script) sets over the scene file; an empty field keeps the file's value.
struct SceneOverrides {
    std::optional<std::string> model;
    std::optional<int> triangles;
    std::optional<physics::Scheme> scheme;
    std::optional<double> solverTolerance;
    std::optional<double> solverForceTolerance_N;
    std::optional<int> solverMaxIterations;
    std::optional<unsigned> solverThreads;
    std::optional<double> rate_hz;
    std::optional<double> couplingStiffness_N_per_m;
    std::optional<std::array<double, 2>> friction;  // static, dynamic
    std::optional<std::string> trajectory;          // the first device replays it
    std::optional<double> scale;                    // the model's scale ([model] scale): --units, --scale
    std::optional<bool> center;                     // [model] center: --center
    std::optional<double> fitSize_m;                // [model] fit_size_m: --fit-size
    std::optional<std::vector<std::string>> parts;  // [model] parts: --part
};

struct SceneRequest {
    std::filesystem::path file;  // a scene file; empty: the built-in default (the heart, a probe and a scalpel)
    std::string overlay;         // TOML set over the file's keys (scene_file.h, parseScene); then the overrides
    SceneOverrides overrides;
};

struct Tool {
    std::string name;
    mesh::SurfaceMesh mesh;  // tip at the origin, handle along +z
    double threshold_N = 1e9;
    double tipRadius_m = 0;  // haptics::Hand::tipRadius_m
};

struct Scene {
    std::filesystem::path file;  // empty for the built-in default
    SceneFile settings;          // the file's, with the overrides applied
    ModelSource source;          // its mesh placed by the scene
    std::vector<Tool> tools;
    physics::MaterialField tissue;  // the [[regions]] (scene/tissue_regions); empty: uniform tissue

    /// The organ's mass-spring model: the scene's material when it gives one, else the model's own, with
    /// its regions' scales.
    physics::MassSpringModel buildModel() const;
    /// The haptic loop's settings the scene gives: integrator, rate, coupling, friction, active region.
    /// Tools' thresholds go with the hands.
    haptics::LoopConfig loopConfig() const;
    /// A fresh organ to simulate and cut, at rest.
    cutting::CutModel makeOrgan() const { return cutting::CutModel(source.mesh, buildModel(), tissue); }
    /// The tool of that name, or nothing (the caller names the choices).
    std::optional<std::size_t> toolIndex(std::string_view name) const;
};

/// What a tool does to the tissue: the force it cuts at (R14) and the radius of its tip.
struct ToolTip {
    double threshold_N = 1e9;
    double radius_m = 0;
};

/// The tip of the tool a command line names: the scene's tool of that name, the procedural probe's
/// or scalpel's, or a thesis tool file's. A name with no '.' that is none of these is an unknown tool
/// (an error without a file); anything else is a file that did not load.
Result<ToolTip, Error> toolTip(const SceneFile& settings, const std::string& name);

/// The scene's loop settings (Scene::loopConfig) with the first hand's tool.
haptics::LoopConfig loopConfigFor(const Scene& scene, const ToolTip& firstHandsTip);

/// Sets the overrides over `settings`.
void applyOverrides(const SceneOverrides& overrides, SceneFile& settings);

/// The scene's settings: the file's (or the built-in default's) with the overrides applied. Reads
/// only the scene file, so a command can check its arguments before a large model loads.
Result<SceneFile, Error> sceneSettings(const SceneRequest& request);
/// Loads and places the model and loads the tools that `settings` (from `file`, or the default) name.
Result<Scene, Error> assembleScene(std::filesystem::path file, SceneFile settings);
/// Both: the whole scene. Errors name the file and line.
Result<Scene, Error> loadScene(const SceneRequest& request);

}  // namespace hapticut::scene
