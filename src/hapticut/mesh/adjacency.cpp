// Edge and face adjacency from the 3F face corners, ordered by their edges.
#include "hapticut/mesh/adjacency.h"

#include <algorithm>

namespace hapticut::mesh {

MeshAdjacency buildAdjacency(std::span<const Face> faces) {
    struct Corner {
        std::uint32_t lo, hi, face, k;
    };
    // The corners in order of their edges' lower vertex, by counting (linear in the mesh), then each
    // vertex's few by the higher vertex and the face: the order one sort of all the corners gives, in a
    // fraction of its time (the cutter's invariant checks build this after every cut, and a large organ
    // at load). Vertex numbers far beyond the corners' count (a malformed file's) are sorted instead.
    auto edgeOf = [&](std::uint32_t f, std::uint32_t k) {
        const std::uint32_t a = faces[f][k], b = faces[f][(k + 1) % 3];
        return Corner{std::min(a, b), std::max(a, b), f, k};
    };
    auto byEdgeAndFace = [](const Corner& x, const Corner& y) {
        return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.face < y.face;
    };
    std::size_t vertices = 0;
    for (const Face& f : faces)
        vertices = std::max<std::size_t>(vertices, std::size_t{std::max({f[0], f[1], f[2]})} + 1);
    std::vector<Corner> corners(3 * faces.size());
    if (vertices > 4 * corners.size() + 1024) {
        for (std::uint32_t f = 0; f < faces.size(); ++f)
            for (std::uint32_t k = 0; k < 3; ++k) corners[3 * f + k] = edgeOf(f, k);
        std::sort(corners.begin(), corners.end(), byEdgeAndFace);
    } else {
        std::vector<std::size_t> start(vertices + 1, 0);
        for (std::uint32_t f = 0; f < faces.size(); ++f)
            for (std::uint32_t k = 0; k < 3; ++k) ++start[edgeOf(f, k).lo + 1];
        for (std::size_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
        std::vector<std::size_t> next(start.begin(), start.end() - 1);
        for (std::uint32_t f = 0; f < faces.size(); ++f)
            for (std::uint32_t k = 0; k < 3; ++k) {
                const Corner c = edgeOf(f, k);
                corners[next[c.lo]++] = c;
            }
        for (std::size_t v = 0; v < vertices; ++v)
            std::sort(corners.begin() + static_cast<std::ptrdiff_t>(start[v]),
                      corners.begin() + static_cast<std::ptrdiff_t>(start[v + 1]), byEdgeAndFace);
    }

    MeshAdjacency adj;
    adj.faceEdges.resize(faces.size());
    adj.faceNeighbours.assign(faces.size(), {kNoFace, kNoFace, kNoFace});
    adj.edgeFaces.reserve(corners.size());
    for (std::size_t i = 0; i < corners.size();) {
        std::size_t j = i;
        while (j < corners.size() && corners[j].lo == corners[i].lo && corners[j].hi == corners[i].hi) ++j;
        const auto e = static_cast<std::uint32_t>(adj.edges.size());
        adj.edges.push_back({corners[i].lo, corners[i].hi});
        adj.edgeFaceStart.push_back(static_cast<std::uint32_t>(adj.edgeFaces.size()));
        for (std::size_t c = i; c < j; ++c) {
            adj.edgeFaces.push_back(corners[c].face);
            adj.faceEdges[corners[c].face][corners[c].k] = e;
        }
        if (j - i == 2) {
            const Corner &p = corners[i], &q = corners[i + 1];
            adj.faceNeighbours[p.face][p.k] = q.face;
            adj.faceNeighbours[q.face][q.k] = p.face;
        }
        i = j;
    }
    adj.edgeFaceStart.push_back(static_cast<std::uint32_t>(adj.edgeFaces.size()));
    return adj;
}

std::vector<std::uint32_t> facePieces(const MeshAdjacency& adjacency, bool manifoldEdgesOnly) {
    std::vector<std::uint32_t> parent(adjacency.faceEdges.size());
    for (std::uint32_t f = 0; f < parent.size(); ++f) parent[f] = f;
    auto root = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (std::size_t e = 0; e < adjacency.edges.size(); ++e) {
        const auto faces = adjacency.facesOfEdge(e);
        if (manifoldEdgesOnly && faces.size() != 2) continue;
        for (std::size_t i = 1; i < faces.size(); ++i) parent[root(faces[i])] = root(faces[0]);
    }
    for (std::uint32_t f = 0; f < parent.size(); ++f) parent[f] = root(f);
    return parent;
}

}  // namespace hapticut::mesh
