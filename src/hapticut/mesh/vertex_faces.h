// The faces around each vertex, for one-ring searches such as the proxy's fast path; cutting keeps it
// up to date as faces are split, so it is a list per vertex rather than one packed array.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh {

struct VertexFaces {
    std::vector<std::vector<std::uint32_t>> around;  // around[v]: the faces that use vertex v

    std::span<const std::uint32_t> of(std::uint32_t v) const { return around[v]; }
};

VertexFaces buildVertexFaces(std::span<const Face> faces, std::size_t vertex_count);

}  // namespace hapticut::mesh
