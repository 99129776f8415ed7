// Gathering and finishing imported triangles.
#include "hapticut/mesh/io/imported_mesh.h"

#include <algorithm>

#include "hapticut/geometry/triangle.h"

namespace hapticut::mesh::io {

void ImportedMeshBuilder::beginPart(const std::string& name) {
    auto& names = out_.mesh.partNames;
    const auto it = std::find(names.begin(), names.end(), name);
    part_ = static_cast<std::uint32_t>(it - names.begin());
    if (it == names.end()) names.push_back(name);
}

void ImportedMeshBuilder::addFace(const Face& f, const FaceUvs& uvs) {
    SurfaceMesh& m = out_.mesh;
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] ||
        geometry::areaNormal(m.positions[f[0]], m.positions[f[1]], m.positions[f[2]]).squaredNorm() == 0) {
        ++degenerate_;
        return;
    }
    m.faces.push_back(f);
    m.uvs.push_back(uvs);
    if (m.partNames.empty()) m.partNames.emplace_back();  // faces before any part's name
    m.faceParts.push_back(part_);
}

void nameParts(SurfaceMesh& m, const std::string& fallback) {
    if (m.faceParts.size() != m.faces.size()) {
        m.faceParts.clear();
        m.partNames.clear();
        return;
    }
    std::vector<std::uint32_t> faces(m.partNames.size(), 0), renumber(m.partNames.size(), 0);
    for (std::uint32_t p : m.faceParts) ++faces[p];
    std::vector<std::string> names;
    for (std::size_t p = 0; p < m.partNames.size(); ++p) {
        if (faces[p] == 0) continue;
        renumber[p] = static_cast<std::uint32_t>(names.size());
        std::string name = m.partNames[p];
        if (name.empty()) name = names.empty() && !fallback.empty() ? fallback : "part " + std::to_string(p + 1);
        while (std::find(names.begin(), names.end(), name) != names.end()) name += "'";
        names.push_back(std::move(name));
    }
    if (names.size() < 2) {
        m.faceParts.clear();
        m.partNames.clear();
        return;
    }
    for (std::uint32_t& p : m.faceParts) p = renumber[p];
    m.partNames = std::move(names);
}

Result<ImportedMesh, Error> ImportedMeshBuilder::finish(const std::filesystem::path& file, std::string_view expected) {
    if (out_.mesh.faces.empty()) return unexpected(Error{file, 0, "no faces found: expected " + std::string(expected)});
    if (degenerate_ > 0)
        out_.warnings.push_back({file, 0, "dropped " + std::to_string(degenerate_) + " degenerate face(s)"});
    nameParts(out_.mesh, file.stem().string());
    completeMesh(out_.mesh);
    return std::move(out_);
}

}  // namespace hapticut::mesh::io
