// Scene, model and tools for the commands that draw.
#include "scene_setup.h"

#include <iostream>

#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"

namespace hapticut::app {

physics::MassSpringModel LoadedScene::buildModel() const {
    if (settings.materialGiven) return physics::buildModel(source.mesh, settings.material);
    return buildSimulationModel(source);
}

std::optional<std::size_t> LoadedScene::toolIndex(const std::string& name) const {
    for (std::size_t i = 0; i < tools.size(); ++i)
        if (tools[i].name == name) return i;
    return std::nullopt;
}

std::optional<LoadedScene> loadScene(const SceneChoice& choice) {
    LoadedScene loaded;
    if (choice.scene.empty()) {
        loaded.settings = scene::defaultScene();
    } else {
        auto file = scene::readScene(choice.scene);
        if (!file) {
            std::cerr << file.error().toString() << "\n";
            return std::nullopt;
        }
        loaded.settings = std::move(*file);
    }
    if (choice.model) loaded.settings.model = *choice.model;
    if (choice.triangles) loaded.settings.triangles = *choice.triangles;
    auto source = loadModelSource(loaded.settings.model, loaded.settings.triangles);
    if (!source) return std::nullopt;
    loaded.source = std::move(*source);
    scene::applyPlacement(loaded.settings, loaded.source.mesh.positions);
    mesh::computeFaceNormals(loaded.source.mesh);

    for (const scene::SceneTool& t : loaded.settings.tools) {
        LoadedTool tool{t.name, {}, t.threshold_N};
        if (!t.file.empty()) {
            auto file = mesh::io::readToolFile(t.file);
            if (!file) {
                std::cerr << file.error().toString() << "\n";
                return std::nullopt;
            }
            tool.mesh = std::move(file->mesh);
        } else {
            tool.mesh = t.name == "scalpel" ? mesh::procedural::makeScalpel() : mesh::procedural::makeProbe();
        }
        loaded.tools.push_back(std::move(tool));
    }
    return loaded;
}

}  // namespace hapticut::app
