// What the OBJ and PLY readers produce, and the one way they gather and finish its triangles.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh::io {

struct ImportedMesh {
    SurfaceMesh mesh;  // edges from the faces, normals computed
    std::vector<Warning> warnings;
};

/// Finishes the parts of a mesh whose faceParts a reader filled: parts without faces go, an unnamed
/// one is called `fallback` (the file's stem) or "part N", and a model of one part has none.
void nameParts(SurfaceMesh& mesh, const std::string& fallback);

/// Collects the triangles a reader parses. Degenerate ones (a repeated corner, or zero area) are
/// dropped and counted: the simulation cannot give them a normal or spread a force over them.
class ImportedMeshBuilder {
public:
    SurfaceMesh& mesh() { return out_.mesh; }
    /// The faces added from now on are in the part of this name (an OBJ group, an imported mesh).
    void beginPart(const std::string& name);
    void addFace(const Face& face, const FaceUvs& uvs);
    /// The finished mesh with a warning for the dropped faces; an error saying `expected` (what would
    /// have been faces) when none is left.
    Result<ImportedMesh, Error> finish(const std::filesystem::path& file, std::string_view expected);

private:
    ImportedMesh out_;
    std::size_t degenerate_ = 0;
    std::uint32_t part_ = 0;
};

}  // namespace hapticut::mesh::io
