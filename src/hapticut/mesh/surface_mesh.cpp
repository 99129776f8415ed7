// SurfaceMesh helpers: edges from faces, normals, area.
#include "hapticut/mesh/surface_mesh.h"

#include <algorithm>

#include "hapticut/geometry/triangle.h"

namespace hapticut::mesh {

std::vector<Edge> edgesOfFaces(std::span<const Face> faces) {
    std::vector<Edge> edges;
    edges.reserve(faces.size() * 3);
    for (const Face& f : faces)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = f[k], b = f[(k + 1) % 3];
            edges.push_back({std::min(a, b), std::max(a, b)});
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
}

void computeFaceNormals(SurfaceMesh& mesh) {
    mesh.normals.resize(mesh.faces.size());
    for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
        const Face& f = mesh.faces[i];
        mesh.normals[i] = geometry::unitNormal(mesh.positions[f[0]], mesh.positions[f[1]], mesh.positions[f[2]]);
    }
}

void completeMesh(SurfaceMesh& mesh) {
    if (mesh.uvs.size() != mesh.faces.size())
        mesh.uvs.assign(mesh.faces.size(), FaceUvs{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()});
    if (mesh.normals.size() != mesh.faces.size()) computeFaceNormals(mesh);
    if (mesh.edges.empty()) mesh.edges = edgesOfFaces(mesh.faces);
}

double surfaceArea(const SurfaceMesh& mesh) {
    double area = 0;
    for (const Face& f : mesh.faces)
        area += geometry::triangleArea(mesh.positions[f[0]], mesh.positions[f[1]], mesh.positions[f[2]]);
    return area;
}

double meanEdgeLength(const SurfaceMesh& mesh) {
    if (mesh.edges.empty()) return 0;
    double sum = 0;
    for (const Edge& e : mesh.edges) sum += (mesh.positions[e[1]] - mesh.positions[e[0]]).norm();
    return sum / static_cast<double>(mesh.edges.size());
}

}  // namespace hapticut::mesh
