// The walls of an opened wound, for the eye (SPEC beyond): a strip hangs from each lip into the organ,
// slanting toward the other lip, so an opened cut shows raw tissue with depth instead of a hole.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_set>
#include <vector>

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::cutting {

/// A boundary edge of the surface, a -> b in the winding of its one face.
struct LipEdge {
    std::uint32_t a = 0, b = 0;
};

/// The edges a cut opened: boundary edges of `faces` that are not in `rims` (the boundary of the uncut
/// organ, from rimEdges()), so an open organ's own rim grows no wall.
std::vector<LipEdge> lipEdges(std::span<const mesh::Face> faces, const std::unordered_set<std::uint64_t>& rims = {});
/// The boundary edges of `faces` as keys (lower index << 32 | higher): pass the uncut organ's to lipEdges.
std::unordered_set<std::uint64_t> rimEdges(std::span<const mesh::Face> faces);

struct WallParams {
    /// How deep the walls reach, as a multiple of the lips' mean edge length.
    double depthPerEdge = 0.9;
    /// How far each wall's foot leans toward the other lip, as a fraction of the depth: the two walls
    /// of a wound nearly meet at the bottom, as the sides of a V-shaped incision do.
    double lean = 0.35;
};

/// Walls over the current positions: for each lip vertex a foot below it, and for each lip edge two
/// triangles from the lip down to the feet, facing into the gap. Wall vertices 0..n-1 are the lip
/// vertices, n..2n-1 their feet. Each wall vertex has its own UV for the wall's material: v runs from 0
/// at the lip to 1 at the foot, u along the lip in wall depths.
class WoundWalls {
public:
    /// After a cut: which lips hang walls, and the walls' triangles.
    void setLips(std::span<const LipEdge> lips);
    /// Every frame: the wall vertices over the surface's positions and unit outward vertex normals.
    /// Never allocates.
    void update(std::span<const Vec3> positions, std::span<const Vec3> vertexNormals, const WallParams& params = {});

    std::span<const std::uint32_t> lipVertices() const {
        return lipVertex_;
    }  // the surface vertex of wall vertex i < n
    std::span<const Vec3> positions() const { return positions_; }
    std::span<const Vec3> normals() const { return normals_; }  // unit, facing into the gap
    std::span<const Vec2> uvs() const { return uvs_; }
    std::span<const mesh::Face> faces() const { return faces_; }
    double depth_m() const { return depth_m_; }
    bool empty() const { return faces_.empty(); }

private:
    std::vector<LipEdge> lips_;  // in wall vertex indices
    std::vector<std::uint32_t> lipVertex_;
    std::vector<Vec3> positions_, normals_, across_;
    std::vector<Vec2> uvs_;
    std::vector<mesh::Face> faces_;
    double depth_m_ = 0;
};

}  // namespace hapticut::cutting
