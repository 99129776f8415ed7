// Assembling a scene: settings, overrides, the placed model and the tools.
#include "hapticut/scene/scene.h"

#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/assessment.h"
#include "hapticut/scene/model_size.h"
#include "hapticut/scene/tissue_regions.h"

namespace hapticut::scene {

physics::MassSpringModel Scene::buildModel() const {
    physics::MassSpringModel model =
        settings.materialGiven ? physics::buildModel(source.mesh, settings.material) : buildSimulationModel(source);
    physics::applyMaterialField(model, tissue);
    return model;
}

haptics::LoopConfig Scene::loopConfig() const {
    haptics::LoopConfig config;
    config.scheme = settings.scheme;
    config.solver = settings.solver;
    config.physicsRate = settings.physicsRate;
    config.rate_hz = settings.rate_hz;
    config.hapticThreadPriority = settings.hapticThreadPriority;
    config.maxPhysicsStep_s = settings.maxPhysicsStep_s;
    config.couplingStiffness_N_per_m = settings.couplingStiffness_N_per_m;
    config.couplingDamping_Ns_per_m = settings.couplingDamping_Ns_per_m;
    config.activeRegion = settings.activeRegion;
    config.proxy.staticFriction = settings.staticFriction;
    config.proxy.dynamicFriction = settings.dynamicFriction;
    config.toughness_J_per_m2 = settings.toughness_J_per_m2;
    config.bulkModulus_Pa = settings.bulkModulus_Pa;
    config.strainLimit = settings.strainLimit;
    return config;
}

haptics::LoopConfig loopConfigFor(const Scene& scene, const ToolTip& firstHandsTip) {
    haptics::LoopConfig config = scene.loopConfig();
    config.cutThreshold_N = firstHandsTip.threshold_N;
    config.tipRadius_m = firstHandsTip.radius_m;
    return config;
}

std::optional<std::size_t> Scene::toolIndex(std::string_view name) const {
    for (std::size_t i = 0; i < tools.size(); ++i)
        if (tools[i].name == name) return i;
    return std::nullopt;
}

Result<ToolTip, Error> toolTip(const SceneFile& settings, const std::string& name) {
    for (const SceneTool& t : settings.tools)
        if (t.name == name) return ToolTip{t.threshold_N, t.tipRadius_m};
    if (name == "probe") return ToolTip{mesh::procedural::kProbeThreshold_N, mesh::procedural::kProbeTipRadius_m};
    if (name == "scalpel") return ToolTip{mesh::procedural::kScalpelThreshold_N, mesh::procedural::kScalpelTipRadius_m};
    if (name.find('.') == std::string::npos)
        return unexpected(
            Error{{}, 0, "unknown tool '" + name + "': expected probe, scalpel or a tool file (thesis format)"});
    auto tool = mesh::io::readToolFile(name);
    if (!tool) return unexpected(tool.error());
    return ToolTip{tool->threshold_N, mesh::procedural::tipRadiusForThreshold_m(tool->threshold_N)};
}

void applyOverrides(const SceneOverrides& o, SceneFile& s) {
    if (o.model) s.model = *o.model;
    if (o.triangles) s.triangles = *o.triangles;
    if (o.scale) s.scale = *o.scale;
    if (o.center) s.center = *o.center;
    if (o.fitSize_m) s.fitSize_m = *o.fitSize_m;
    if (o.parts) s.parts = *o.parts;
    if (o.scheme) s.scheme = *o.scheme;
    if (o.solverTolerance) s.solver.tolerance = *o.solverTolerance;
    if (o.solverForceTolerance_N) s.solver.forceTolerance_N = *o.solverForceTolerance_N;
    if (o.solverMaxIterations) s.solver.maxIterations = *o.solverMaxIterations;
    if (o.solverThreads) s.solver.threads = *o.solverThreads;
    if (o.rate_hz) s.rate_hz = *o.rate_hz;
    if (o.couplingStiffness_N_per_m) s.couplingStiffness_N_per_m = *o.couplingStiffness_N_per_m;
    if (o.friction) s.staticFriction = (*o.friction)[0], s.dynamicFriction = (*o.friction)[1];
    if (o.trajectory) {
        s.deviceBackend = "replay";
        s.trajectory = *o.trajectory;
    }
}

Result<SceneFile, Error> sceneSettings(const SceneRequest& request) {
    SceneFile settings;
    if (request.file.empty() && request.overlay.empty()) {
        settings = defaultScene();
    } else {
        auto file = request.file.empty() ? parseScene("", {}, std::filesystem::current_path(), request.overlay)
                                         : readScene(request.file, request.overlay);
        if (!file) return unexpected(file.error());
        settings = std::move(*file);
    }
    applyOverrides(request.overrides, settings);
    return settings;
}

Result<Scene, Error> assembleScene(std::filesystem::path file, SceneFile settings) {
    Scene scene;
    scene.file = std::move(file);
    scene.settings = std::move(settings);
    auto source = loadModelSource(scene.settings.model, scene.settings.triangles, scene.settings.parts);
    if (!source) return unexpected(source.error());
    scene.source = std::move(*source);
    applyPlacement(scene.settings, scene.source.mesh.positions);
    describeInMetres(scene.source);
    auto tissue = materialField(scene.settings.regions, scene.file);
    if (!tissue) return unexpected(tissue.error());
    scene.tissue = std::move(*tissue);
    if (auto off = checkExercisePlacement(scene, kExercisePointTolerance_m)) return unexpected(std::move(*off));
    if (auto unusual = sizeWarning(scene.source.mesh.positions, scene.source.name))
        scene.source.warnings.push_back(std::move(*unusual));
    if (auto away = offCentreWarning(scene.source.mesh.positions, scene.source.name))
        scene.source.warnings.push_back(std::move(*away));
    mesh::computeFaceNormals(scene.source.mesh);
    for (const SceneTool& t : scene.settings.tools) {
        Tool tool{t.name, {}, t.threshold_N, t.tipRadius_m};
        if (!t.file.empty()) {
            auto toolFile = mesh::io::readToolFile(t.file);
            if (!toolFile) return unexpected(toolFile.error());
            tool.mesh = std::move(toolFile->mesh);
        } else {
            tool.mesh = t.name == "scalpel" ? mesh::procedural::makeScalpel() : mesh::procedural::makeProbe();
        }
        scene.tools.push_back(std::move(tool));
    }
    return scene;
}

Result<Scene, Error> loadScene(const SceneRequest& request) {
    auto settings = sceneSettings(request);
    if (!settings) return unexpected(settings.error());
    return assembleScene(request.file, std::move(*settings));
}

}  // namespace hapticut::scene
