// The faces around each vertex.
#include "hapticut/mesh/vertex_faces.h"

namespace hapticut::mesh {

VertexFaces buildVertexFaces(std::span<const Face> faces, std::size_t vertex_count) {
    VertexFaces vf;
    vf.start.assign(vertex_count + 1, 0);
    for (const Face& f : faces)
        for (std::uint32_t v : f) ++vf.start[v + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) vf.start[v + 1] += vf.start[v];
    vf.faces.resize(vf.start.back());
    std::vector<std::uint32_t> fill(vf.start.begin(), vf.start.end() - 1);
    for (std::uint32_t f = 0; f < faces.size(); ++f)
        for (std::uint32_t v : faces[f]) vf.faces[fill[v]++] = f;
    return vf;
}

}  // namespace hapticut::mesh
