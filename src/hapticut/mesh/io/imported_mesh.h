// What the OBJ and PLY readers produce, and the one way they gather and finish its triangles.
#pragma once

#include <cstddef>
#include <filesystem>
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

/// Collects the triangles a reader parses. Degenerate ones (a repeated corner, or zero area) are
/// dropped and counted: the simulation cannot give them a normal or spread a force over them.
class ImportedMeshBuilder {
public:
    SurfaceMesh& mesh() { return out_.mesh; }
    void addFace(const Face& face, const FaceUvs& uvs);
    /// The finished mesh with a warning for the dropped faces; an error saying `expected` (what would
    /// have been faces) when none is left.
    Result<ImportedMesh, Error> finish(const std::filesystem::path& file, std::string_view expected);

private:
    ImportedMesh out_;
    std::size_t degenerate_ = 0;
};

}  // namespace hapticut::mesh::io
