// A model's named parts (an atlas heart's chambers, valves and vessels): choosing some, and what each is.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh {

/// Keeps only the faces of the named parts (and the vertices they use), in the order the names are
/// given among the parts kept. An error message, with the model's parts listed, when a name is not
/// one of them or the model has none; the mesh is unchanged then.
std::optional<std::string> selectParts(SurfaceMesh& mesh, std::span<const std::string> names);

struct PartSummary {
    std::string name;
    std::size_t faces = 0, vertices = 0, boundaryEdges = 0;
    bool closed() const { return boundaryEdges == 0; }
};

/// Each part's size and whether it is closed on its own; empty for a model of one part.
std::vector<PartSummary> summariseParts(const SurfaceMesh& mesh);

/// The parts' names joined for a message: "'atrium', 'valve' and 'vessel'".
std::string listParts(const SurfaceMesh& mesh);

}  // namespace hapticut::mesh
