// Edge and face adjacency built by one sort of the 3F face corners.
#include "hapticut/mesh/adjacency.h"

#include <algorithm>

namespace hapticut::mesh {

MeshAdjacency buildAdjacency(std::span<const Face> faces) {
    struct Corner {
        std::uint32_t lo, hi, face, k;
    };
    std::vector<Corner> corners;
    corners.reserve(faces.size() * 3);
    for (std::uint32_t f = 0; f < faces.size(); ++f)
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t a = faces[f][k], b = faces[f][(k + 1) % 3];
            corners.push_back({std::min(a, b), std::max(a, b), f, k});
        }
    std::sort(corners.begin(), corners.end(), [](const Corner& x, const Corner& y) {
        return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.face < y.face;
    });

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
