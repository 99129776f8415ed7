// The organ as the GPU draws it: one render vertex per distinct (vertex, UV) pair, smooth normals
// recomputed from the deformed positions every frame.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/mesh/surface_mesh.h"
#include "render/vertex_layout.h"

namespace hapticut::render {

class OrganSurface {
public:
    /// After a cut (or at the start): which render vertices exist and the triangles over them. A vertex
    /// on a UV seam becomes several render vertices that share one normal, so seams do not show; the two
    /// lips of a cut are different vertices, so the lips stay sharp.
    void setTopology(std::span<const mesh::Face> faces, std::span<const mesh::FaceUvs> uvs, std::size_t vertexCount);
    /// Every frame: area-weighted vertex normals of the deformed surface, then the interleaved vertices.
    void update(std::span<const Vec3> positions);

    std::span<const float> vertices() const { return vertices_; }
    std::span<const std::uint32_t> indices() const { return indices_; }
    std::size_t renderVertexCount() const { return source_.size(); }
    /// The unit normal of model vertex i after the last update (zero for an unused vertex).
    const Vec3& vertexNormal(std::size_t i) const { return normals_[i]; }
    /// Whether model vertex i lies on an open boundary: the lip of a cut (or an open mesh's rim).
    bool onLip(std::size_t i) const { return lip_[i] != 0; }

private:
    std::vector<std::uint32_t> source_;  // render vertex -> model vertex
    std::vector<float> uv_;              // two per render vertex
    std::vector<std::uint32_t> indices_;
    std::vector<mesh::Face> faces_;
    std::vector<Vec3> normals_;
    std::vector<std::uint8_t> lip_;
    std::vector<float> vertices_;
};

}  // namespace hapticut::render
