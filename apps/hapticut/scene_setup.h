// What `view` and `screenshot` show: a scene file or the built-in default, with --model/--triangles
// overriding it, resolved into a placed organ, its model and the tools' meshes and thresholds.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "hapticut/scene/scene_file.h"
#include "model_source.h"

namespace hapticut::app {

struct SceneChoice {
    std::string scene;                 // a scene file; empty: the built-in default
    std::optional<std::string> model;  // overrides the scene's model
    std::optional<int> triangles;
};

struct LoadedTool {
    std::string name;
    mesh::SurfaceMesh mesh;  // tip at the origin, handle along +z
    double threshold_N = 1e9;
};

struct LoadedScene {
    scene::SceneFile settings;
    ModelSource source;  // placed by the scene
    std::vector<LoadedTool> tools;

    physics::MassSpringModel buildModel() const;
    /// The tool of that name, or nothing (the caller names the choices).
    std::optional<std::size_t> toolIndex(const std::string& name) const;
};

/// Loads everything; on failure prints what and where (file:line) to stderr and returns nothing.
std::optional<LoadedScene> loadScene(const SceneChoice& choice);

}  // namespace hapticut::app
