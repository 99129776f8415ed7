// Resolves `--model heart|FILE [--triangles N]` into a mesh and a ready-to-step mass-spring model.
#pragma once

#include <optional>
#include <string>

#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/physics/mass_spring_model.h"

namespace hapticut::app {

struct ModelSource {
    std::string name;                   // "heart" or the file path
    mesh::SurfaceMesh mesh;
    mesh::io::ThesisPhysics physics;    // as loaded, or the thesis equivalent of the default material
    std::optional<double> toolThreshold_N;
    bool fromThesisFile = false;
};

/// Loads the model; on failure prints "file:line: message" to stderr and returns nothing.
/// Warnings are printed to stderr and loading goes on.
std::optional<ModelSource> loadModelSource(const std::string& model, int triangles);

/// The simulation model: a thesis file's own constants, otherwise the default resolution-independent material.
physics::MassSpringModel buildSimulationModel(const ModelSource& source);

}  // namespace hapticut::app
