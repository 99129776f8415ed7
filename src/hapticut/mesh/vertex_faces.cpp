// The faces around each vertex.
#include "hapticut/mesh/vertex_faces.h"

namespace hapticut::mesh {

VertexFaces buildVertexFaces(std::span<const Face> faces, std::size_t vertex_count) {
    VertexFaces vf;
    vf.around.resize(vertex_count);
    std::vector<std::uint32_t> count(vertex_count, 0);
    for (const Face& f : faces)
        for (std::uint32_t v : f) ++count[v];
    for (std::size_t v = 0; v < vertex_count; ++v) vf.around[v].reserve(count[v]);
    for (std::uint32_t f = 0; f < faces.size(); ++f)
        for (std::uint32_t v : faces[f]) vf.around[v].push_back(f);
    return vf;
}

}  // namespace hapticut::mesh
