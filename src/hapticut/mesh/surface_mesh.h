// SurfaceMesh: an indexed triangle surface with rest positions, per-corner UVs, face normals and springs' edges.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/geometry/vec.h"

namespace hapticut::mesh {

using Face = std::array<std::uint32_t, 3>;  // vertex indices, counter-clockwise seen from outside
using Edge = std::array<std::uint32_t, 2>;
using FaceUvs = std::array<Vec2, 3>;  // one UV per corner, so a vertex can sit on a texture seam

/// The thesis's indexed face set (SPEC R1). Physics reads only `positions` and `edges`.
struct SurfaceMesh {
    std::vector<Vec3> positions;  // m, the undeformed (rest) shape
    std::vector<Face> faces;
    std::vector<FaceUvs> uvs;   // per face, same length as faces
    std::vector<Vec3> normals;  // per face, unit length
    std::vector<Edge> edges;    // structural springs; normally every face edge exactly once

    std::size_t vertexCount() const { return positions.size(); }
    std::size_t faceCount() const { return faces.size(); }
};

/// One number for the undirected edge (a, b), the same either way round: for hash sets and maps.
inline std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
}

/// The unique undirected edges of the faces, each as {lower, higher} index, sorted.
std::vector<Edge> edgesOfFaces(std::span<const Face> faces);

/// Recomputes unit face normals from the positions (zero for degenerate faces).
void computeFaceNormals(SurfaceMesh& mesh);

/// Fills missing UVs (zero), normals (computed) and edges (from faces) so the mesh is complete.
void completeMesh(SurfaceMesh& mesh);

/// Whether face f's winding runs from a straight to b (a and b are consecutive corners in that order).
/// Two faces on an edge are consistently oriented when exactly one of them runs a -> b.
inline bool traversesForward(const Face& f, std::uint32_t a, std::uint32_t b) {
    for (int k = 0; k < 3; ++k)
        if (f[k] == a && f[(k + 1) % 3] == b) return true;
    return false;
}

/// Total surface area in m^2.
double surfaceArea(const SurfaceMesh& mesh);

/// Mean length of the structural edges in m (0 when there are none).
double meanEdgeLength(const SurfaceMesh& mesh);

}  // namespace hapticut::mesh
