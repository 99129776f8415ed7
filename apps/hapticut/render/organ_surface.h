// The organ as the GPU draws it: one render vertex per distinct (vertex, UV, material) triple, smooth
// normals recomputed from the deformed positions every frame, the walls of wounds in their own material.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_set>
#include <vector>

#include "hapticut/mesh/surface_mesh.h"
#include "render/vertex_layout.h"

namespace hapticut::render {

class OrganSurface {
public:
    /// The organ before any cut: its open rims (if any) are not the lips of a wound.
    void setRims(std::span<const mesh::Face> uncutFaces);
    /// After a cut (or at the start): which render vertices exist and the triangles over them. A vertex
    /// on a UV seam becomes several render vertices that share one normal, so seams do not show. Faces
    /// flagged in `walls` (CutModel::wallFaces; may be empty) are the walls of wounds: their vertices
    /// are render vertices of their own, with normals of the walls alone, so the lips stay sharp.
    void setTopology(std::span<const mesh::Face> faces, std::span<const mesh::FaceUvs> uvs,
                     std::span<const std::uint8_t> walls, std::size_t vertexCount);
    /// Every frame: area-weighted vertex normals of the deformed surface and of the walls, then the
    /// interleaved vertices (wound attribute 2 on the walls, for their own material).
    void update(std::span<const Vec3> positions);
    /// Whether to draw the walls inside wounds; takes effect at the next setTopology.
    void setWallsShown(bool shown) { wallsShown_ = shown; }

    std::span<const float> vertices() const { return vertices_; }
    std::span<const std::uint32_t> indices() const { return indices_; }
    std::size_t renderVertexCount() const { return source_.size(); }
    /// The unit normal of model vertex i on the organ's surface after the last update (zero if unused).
    const Vec3& vertexNormal(std::size_t i) const { return normals_[i]; }
    /// The lip of a wound: a vertex of the surface and of a wall, or on an open boundary that is not the
    /// uncut organ's own rim (a wound left without walls).
    bool onLip(std::size_t i) const { return lip_[i] != 0; }

private:
    std::vector<std::uint32_t> source_;     // render vertex -> model vertex
    std::vector<std::uint8_t> sourceWall_;  // render vertex -> 1 on a wall
    std::vector<float> uv_;                 // two per render vertex
    std::vector<std::uint32_t> indices_;
    std::vector<mesh::Face> faces_;
    std::vector<std::uint8_t> walls_;          // per face
    std::vector<Vec3> normals_, wallNormals_;  // per model vertex
    std::vector<std::uint8_t> lip_;
    std::vector<float> vertices_;
    std::unordered_set<std::uint64_t> rims_;  // the uncut organ's open edges
    bool wallsShown_ = true;
};

}  // namespace hapticut::render
