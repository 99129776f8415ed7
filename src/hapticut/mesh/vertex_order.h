// Vertex order for memory locality: a mesh whose vertices come in no spatial order (a decimator's or an
// exporter's) makes every spring, product and refit jump through memory; renumbered in reverse
// Cuthill-McKee order, neighbours sit close together in every per-node array.
#pragma once

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh {

/// The mean distance in index between the two ends of the mesh's edges: what a pass over the springs
/// jumps through per-node arrays. 0 for a mesh without edges.
double meanEdgeSpan(const SurfaceMesh& mesh);

struct VertexOrderResult {
    bool renumbered = false;
    double spanBefore = 0, spanAfter = 0;  // meanEdgeSpan
    /// Renumbered: the index each vertex had before (in the file), so a script can map its own data.
    std::vector<std::uint32_t> previousIndex;
};

/// Renumbers the vertices in reverse Cuthill-McKee order over the edges, one connected part after
/// another, and sorts the faces by their lowest vertex and the edges as edgesOfFaces does, when that
/// brings the edges' mean span down to less than a quarter of what it was; otherwise leaves the mesh as
/// it is (an order already local, such as the procedural heart's or a marching-cubes surface's, is
/// kept). UVs, normals and parts go with their faces.
VertexOrderResult orderVerticesForLocality(SurfaceMesh& mesh);

}  // namespace hapticut::mesh
