// Gathering and finishing imported triangles.
#include "hapticut/mesh/io/imported_mesh.h"

#include "hapticut/geometry/triangle.h"

namespace hapticut::mesh::io {

void ImportedMeshBuilder::addFace(const Face& f, const FaceUvs& uvs) {
    SurfaceMesh& m = out_.mesh;
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] ||
        geometry::areaNormal(m.positions[f[0]], m.positions[f[1]], m.positions[f[2]]).squaredNorm() == 0) {
        ++degenerate_;
        return;
    }
    m.faces.push_back(f);
    m.uvs.push_back(uvs);
}

Result<ImportedMesh, Error> ImportedMeshBuilder::finish(const std::filesystem::path& file, std::string_view expected) {
    if (out_.mesh.faces.empty()) return unexpected(Error{file, 0, "no faces found: expected " + std::string(expected)});
    if (degenerate_ > 0)
        out_.warnings.push_back({file, 0, "dropped " + std::to_string(degenerate_) + " degenerate face(s)"});
    completeMesh(out_.mesh);
    return std::move(out_);
}

}  // namespace hapticut::mesh::io
