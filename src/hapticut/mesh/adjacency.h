// Edge and face adjacency of a triangle mesh: edge list, face edges, edge-to-faces map, face neighbours.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh {

inline constexpr std::uint32_t kNoFace = std::numeric_limits<std::uint32_t>::max();

struct MeshAdjacency {
    std::vector<Edge> edges;                              // unique undirected edges, {lower, higher}, sorted
    std::vector<std::array<std::uint32_t, 3>> faceEdges;  // edge of corner k: (v[k], v[k+1])
    std::vector<std::uint32_t> edgeFaceStart;             // CSR: faces of edge e are edgeFaces[start[e] .. start[e+1])
    std::vector<std::uint32_t> edgeFaces;
    /// Neighbour across the edge of corner k; kNoFace on a boundary or a non-manifold edge (3+ faces).
    std::vector<std::array<std::uint32_t, 3>> faceNeighbours;

    std::span<const std::uint32_t> facesOfEdge(std::size_t e) const {
        return {edgeFaces.data() + edgeFaceStart[e], edgeFaceStart[e + 1] - edgeFaceStart[e]};
    }
};

MeshAdjacency buildAdjacency(std::span<const Face> faces);

/// The piece of each face, named by one face of it (equal numbers, same piece). Faces join across shared edges: every
/// shared edge, or with `manifoldEdgesOnly` only edges exactly two faces share (non-manifold contact then parts
/// pieces).
std::vector<std::uint32_t> facePieces(const MeshAdjacency& adjacency, bool manifoldEdgesOnly);

}  // namespace hapticut::mesh
