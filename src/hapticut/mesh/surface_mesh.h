// SurfaceMesh: an indexed triangle surface with rest positions, per-corner UVs, face normals and springs' edges.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
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
    /// Named parts (an atlas's chambers and valves: OBJ groups, the meshes of glTF, FBX and the rest):
    /// face f is in partNames[faceParts[f]]. Both empty for a model of one part.
    std::vector<std::string> partNames;
    std::vector<std::uint32_t> faceParts;

    std::size_t vertexCount() const { return positions.size(); }
    std::size_t faceCount() const { return faces.size(); }
    bool hasParts() const { return !faceParts.empty(); }
    std::uint32_t partOf(std::size_t face) const { return faceParts.empty() ? 0 : faceParts[face]; }
};

/// Keeps the faces for which keep(f) is true, with their UVs, normals and parts; returns how many went.
template <class Keep>
std::size_t keepFaces(SurfaceMesh& m, Keep&& keep) {
    const bool normals = m.normals.size() == m.faces.size(), uvs = m.uvs.size() == m.faces.size();
    const bool parts = m.faceParts.size() == m.faces.size();
    std::size_t out = 0;
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        if (!keep(f)) continue;
        m.faces[out] = m.faces[f];
        if (uvs) m.uvs[out] = m.uvs[f];
        if (normals) m.normals[out] = m.normals[f];
        if (parts) m.faceParts[out] = m.faceParts[f];
        ++out;
    }
    const std::size_t removed = m.faces.size() - out;
    m.faces.resize(out);
    if (uvs) m.uvs.resize(out);
    if (normals) m.normals.resize(out);
    if (parts) m.faceParts.resize(out);
    return removed;
}

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
