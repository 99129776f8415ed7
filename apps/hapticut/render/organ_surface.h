// The organ as the GPU draws it: one render vertex per distinct (vertex, UV) pair, smooth normals
// recomputed from the deformed positions every frame.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_set>
#include <vector>

#include "hapticut/cutting/wound_walls.h"
#include "hapticut/mesh/surface_mesh.h"
#include "render/vertex_layout.h"

namespace hapticut::render {

class OrganSurface {
public:
    /// The organ before any cut: its open rims (if any) are not wounds and hang no walls.
    void setRims(std::span<const mesh::Face> uncutFaces) { rims_ = cutting::rimEdges(uncutFaces); }
    /// After a cut (or at the start): which render vertices exist and the triangles over them. A vertex
    /// on a UV seam becomes several render vertices that share one normal, so seams do not show; the two
    /// lips of a cut are different vertices, so the lips stay sharp, and hang walls into the gap.
    void setTopology(std::span<const mesh::Face> faces, std::span<const mesh::FaceUvs> uvs, std::size_t vertexCount);
    /// Every frame: area-weighted vertex normals of the deformed surface, then the interleaved vertices,
    /// the walls' last (marked 2 in the wound attribute, for their own material).
    void update(std::span<const Vec3> positions);
    /// Whether to draw the walls inside opened wounds; takes effect at the next setTopology.
    void setWallsShown(bool shown) { wallsShown_ = shown; }
    const cutting::WoundWalls& walls() const { return walls_; }

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
    std::unordered_set<std::uint64_t> rims_;  // the uncut organ's open edges
    cutting::WoundWalls walls_;
    bool wallsShown_ = true;
};

}  // namespace hapticut::render
