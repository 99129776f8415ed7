// The faces around each vertex (compressed rows), for one-ring searches such as the proxy's fast path.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh {

struct VertexFaces {
    std::vector<std::uint32_t> start;  // faces of vertex v are faces[start[v] .. start[v + 1])
    std::vector<std::uint32_t> faces;

    std::span<const std::uint32_t> of(std::uint32_t v) const { return {faces.data() + start[v], start[v + 1] - start[v]}; }
};

VertexFaces buildVertexFaces(std::span<const Face> faces, std::size_t vertex_count);

}  // namespace hapticut::mesh
