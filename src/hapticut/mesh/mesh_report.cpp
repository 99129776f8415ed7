// Validation report of a mesh.
#include "hapticut/mesh/mesh_report.h"

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "hapticut/geometry/aabb.h"
#include "hapticut/geometry/triangle.h"
#include "hapticut/mesh/adjacency.h"

namespace hapticut::mesh {

MeshReport validateMesh(const SurfaceMesh& mesh) {
    MeshReport r;
    r.vertices = mesh.positions.size();
    r.faces = mesh.faces.size();
    r.springs = mesh.edges.size();
    const MeshAdjacency adj = buildAdjacency(mesh.faces);
    r.edges = adj.edges.size();

    for (std::size_t e = 0; e < adj.edges.size(); ++e) {
        const auto faces = adj.facesOfEdge(e);
        if (faces.size() == 1) ++r.boundaryEdges;
        if (faces.size() >= 3) ++r.nonManifoldEdges;
        if (faces.size() == 2) {
            const auto [a, b] = adj.edges[e];
            if (traversesForward(mesh.faces[faces[0]], a, b) == traversesForward(mesh.faces[faces[1]], a, b))
                ++r.misorientedEdges;
        }
    }
    const std::vector<std::uint32_t> piece = facePieces(adj, false);
    for (std::uint32_t f = 0; f < piece.size(); ++f) r.components += piece[f] == f;

    std::vector<char> used(mesh.positions.size(), 0);
    double minAngle = std::numbers::pi;
    for (const Face& f : mesh.faces) {
        for (std::uint32_t v : f) used[v] = 1;
        const double angle = geometry::minAngle(mesh.positions[f[0]], mesh.positions[f[1]], mesh.positions[f[2]]);
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] || angle <= 0) ++r.degenerateFaces;
        minAngle = std::min(minAngle, angle);
    }
    r.unusedVertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
    r.minAngleDeg = mesh.faces.empty() ? 0 : minAngle * 180 / std::numbers::pi;

    std::vector<Edge> springs;
    springs.reserve(mesh.edges.size());
    for (const Edge& e : mesh.edges) springs.push_back({std::min(e[0], e[1]), std::max(e[0], e[1])});
    std::sort(springs.begin(), springs.end());
    for (const Edge& s : springs)
        if (!std::binary_search(adj.edges.begin(), adj.edges.end(), s)) ++r.springsNotOnFaces;
    for (const Edge& e : adj.edges)
        if (!std::binary_search(springs.begin(), springs.end(), e)) ++r.faceEdgesWithoutSpring;

    r.closed = !mesh.faces.empty() && r.boundaryEdges == 0;
    r.manifold = r.nonManifoldEdges == 0;
    r.oriented = r.manifold && r.misorientedEdges == 0;
    const auto usedVertices = static_cast<long>(r.vertices - r.unusedVertices);
    r.eulerCharacteristic = usedVertices - static_cast<long>(r.edges) + static_cast<long>(r.faces);

    if (!mesh.positions.empty()) {
        const geometry::Aabb box = geometry::boundsOf(mesh.positions);
        r.bboxMin = box.min;
        r.bboxMax = box.max;
    }
    r.area_m2 = surfaceArea(mesh);
    double sum = 0, shortest = adj.edges.empty() ? 0 : std::numeric_limits<double>::infinity();
    for (const Edge& e : adj.edges) {
        const double length = (mesh.positions[e[1]] - mesh.positions[e[0]]).norm();
        sum += length;
        shortest = std::min(shortest, length);
    }
    r.shortestEdge_m = shortest;
    r.meanEdgeLength_m = adj.edges.empty() ? 0 : sum / static_cast<double>(adj.edges.size());
    return r;
}

std::optional<std::string> shapeAdvice(const MeshReport& r) {
    if (r.faces == 0 || (r.minAngleDeg >= 5 && r.shortestEdge_m * 20 >= r.meanEdgeLength_m)) return std::nullopt;
    char text[320];
    std::snprintf(text, sizeof text,
                  "badly shaped for simulation: smallest angle %.2g deg, shortest edge %.3g mm against a mean of "
                  "%.3g mm (slivers make contact rough and the physics stiff); hapticut convert --remesh %zu gives "
                  "even triangles on the same surface",
                  r.minAngleDeg, r.shortestEdge_m * 1e3, r.meanEdgeLength_m * 1e3, r.faces);
    return std::string(text);
}

}  // namespace hapticut::mesh
