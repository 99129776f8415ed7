// Resolves a model name (`heart` or a file) into a mesh and the physics a thesis file carries.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/vertex_order.h"
#include "hapticut/physics/mass_spring_model.h"

namespace hapticut::scene {

struct ModelSource {
    std::string name;  // "heart" or the file path
    mesh::SurfaceMesh mesh;
    mesh::io::ThesisPhysics physics;  // as loaded, or the thesis equivalent of the default material
    std::optional<double> toolThreshold_N;
    bool fromThesisFile = false;
    /// A file's vertices renumbered for locality when they came in no spatial order (mesh/vertex_order.h).
    mesh::VertexOrderResult vertexOrder;
    /// What is unusual about the file but did not stop it loading (open or non-manifold surfaces too).
    std::vector<Warning> warnings;
};

/// The procedural heart with `triangles` triangles, or the model file `model`; with `parts`, only the
/// named parts of it (an error listing its parts when one is not there).
Result<ModelSource, Error> loadModelSource(const std::string& model, int triangles,
                                           std::span<const std::string> parts = {});

/// Once the model's coordinates are in metres (after --units, --scale or a scene's placement): the
/// thesis equivalent of the default material (a thesis file keeps its own constants), and what is unusual
/// about its surface (open, non-manifold, inconsistently oriented, badly shaped for simulation), checked
/// once here, appended to the warnings and returned.
std::vector<Warning> describeInMetres(ModelSource& source);

/// The simulation model: a thesis file's own constants, otherwise the default resolution-independent material.
physics::MassSpringModel buildSimulationModel(const ModelSource& source);

}  // namespace hapticut::scene
