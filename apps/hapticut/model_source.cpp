// Resolves `--model heart|FILE` into a mesh and a mass-spring model.
#include "model_source.h"

#include <iostream>

#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/material.h"

namespace hapticut::app {

std::optional<ModelSource> loadModelSource(const std::string& model, int triangles) {
    ModelSource source;
    source.name = model;
    if (model == "heart") {
        mesh::procedural::HeartOptions options;
        options.triangles = triangles;
        source.mesh = mesh::procedural::makeHeart(options);
        source.physics = physics::thesisPhysicsFor(source.mesh, physics::Material{});
        return source;
    }
    auto loaded = mesh::io::loadMesh(model);
    if (!loaded) {
        std::cerr << loaded.error().toString() << "\n";
        return std::nullopt;
    }
    for (const auto& w : loaded->warnings) std::cerr << "warning: " << w.toString() << "\n";
    source.mesh = std::move(loaded->mesh);
    source.toolThreshold_N = loaded->toolThreshold_N;
    source.fromThesisFile = loaded->physics.has_value();
    source.physics = loaded->physics ? *loaded->physics : physics::thesisPhysicsFor(source.mesh, physics::Material{});
    // Open or non-manifold surfaces can still be simulated; say what is unusual and go on.
    const mesh::MeshReport report = mesh::validateMesh(source.mesh);
    if (report.boundaryEdges > 0) std::cerr << "warning: " << model << ": open surface, " << report.boundaryEdges << " boundary edges\n";
    if (report.nonManifoldEdges > 0)
        std::cerr << "warning: " << model << ": " << report.nonManifoldEdges << " non-manifold edges (hapticut convert --repair splits them)\n";
    if (report.misorientedEdges > 0)
        std::cerr << "warning: " << model << ": inconsistently oriented faces (hapticut convert --repair orients them)\n";
    return source;
}

physics::MassSpringModel buildSimulationModel(const ModelSource& source) {
    if (source.fromThesisFile) return physics::buildModel(source.mesh, source.physics);
    return physics::buildModel(source.mesh, physics::Material{});
}

}  // namespace hapticut::app
