// Resolves `heart` or a file into a mesh and a mass-spring model.
#include "hapticut/scene/model_source.h"

#include <new>

#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/parts.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/repair.h"
#include "hapticut/physics/material.h"

namespace hapticut::scene {

namespace {

/// The model; may throw std::bad_alloc, which loadModelSource turns into an error.
Result<ModelSource, Error> loadOrThrow(const std::string& model, int triangles, std::span<const std::string> parts) {
    ModelSource source;
    source.name = model;
    if (model == "heart") {
        if (!parts.empty()) return unexpected(Error{model, 0, "the procedural heart has no named parts"});
        mesh::procedural::HeartOptions options;
        options.triangles = triangles;
        source.mesh = mesh::procedural::makeHeart(options);
        source.vertexOrder.spanBefore = source.vertexOrder.spanAfter = mesh::meanEdgeSpan(source.mesh);
        return source;
    }
    auto loaded = mesh::io::loadMesh(model);
    if (!loaded) return unexpected(loaded.error());
    source.warnings = std::move(loaded->warnings);
    source.mesh = std::move(loaded->mesh);
    if (const auto refused = mesh::selectParts(source.mesh, parts)) return unexpected(Error{model, 0, *refused});
    // An inside-out part was pressed from outside as if from within: the proxy sank 3.6 mm into a
    // segmented ball and the tissue stayed dented after the tool left.
    const mesh::TurnedOutward turned = mesh::turnInsideOutPiecesOutward(source.mesh);
    if (turned.pieces > 0) {
        std::string which;
        for (const std::string& part : turned.parts) which += (which.empty() ? "part '" : ", '") + part + "'";
        if (which.empty()) which = std::to_string(turned.pieces) + (turned.pieces == 1 ? " piece" : " pieces");
        source.warnings.push_back(
            {model, 0,
             which + " came inside out (" + std::to_string(turned.faces) +
                 " faces whose normals pointed into the tissue): turned outward, as contact and volume need"});
    }
    source.toolThreshold_N = loaded->toolThreshold_N;
    source.fromThesisFile = loaded->physics.has_value();
    if (source.mesh.faces.empty())
        return unexpected(Error{model, 0, "the model has no faces: nothing to touch or simulate"});
    // Every per-node pass of the physics, the tree and the cutter reads neighbours together: a mesh in no
    // spatial order made a fully awake implicit step of a 100,000-triangle heart 1.7 times as slow.
    source.vertexOrder = mesh::orderVerticesForLocality(source.mesh);
    if (loaded->physics) source.physics = *loaded->physics;
    return source;
}

}  // namespace

Result<ModelSource, Error> loadModelSource(const std::string& model, int triangles,
                                           std::span<const std::string> parts) {
    try {
        return loadOrThrow(model, triangles, parts);
    } catch (const std::bad_alloc&) {
        // A model larger than memory (a heart of billions of triangles, a huge file) is an input error.
        return unexpected(
            Error{model, 0,
                  "out of memory loading the model" +
                      (model == "heart" ? " at " + std::to_string(triangles) + " triangles" : std::string())});
    }
}

std::vector<Warning> describeInMetres(ModelSource& source) {
    // Computed on the file's own coordinates, an organ in millimetres was said to have edges a thousand
    // times too long and springs of a thousandth of their stiffness.
    if (!source.fromThesisFile) source.physics = physics::thesisPhysicsFor(source.mesh, physics::Material{});
    if (source.name == "heart") return {};  // closed, manifold and evenly shaped by construction, at any size
    // Open or non-manifold surfaces can still be simulated; say what is unusual and go on.
    const mesh::MeshReport report = mesh::validateMesh(source.mesh);
    std::vector<Warning> found;
    auto warn = [&](std::string message) { found.push_back({source.name, 0, std::move(message)}); };
    if (report.boundaryEdges > 0) warn("open surface, " + std::to_string(report.boundaryEdges) + " boundary edges");
    if (report.nonManifoldEdges > 0)
        warn(std::to_string(report.nonManifoldEdges) + " non-manifold edges (hapticut convert --repair splits them)");
    if (report.misorientedEdges > 0) warn("inconsistently oriented faces (hapticut convert --repair orients them)");
    if (const auto advice = mesh::shapeAdvice(report)) warn(*advice);
    source.warnings.insert(source.warnings.end(), found.begin(), found.end());
    return found;
}

physics::MassSpringModel buildSimulationModel(const ModelSource& source) {
    if (source.fromThesisFile) return physics::buildModel(source.mesh, source.physics);
    return physics::buildModel(source.mesh, physics::Material{});
}

}  // namespace hapticut::scene
