// Wound walls hung from the lips of opened cuts.
#include "hapticut/cutting/wound_walls.h"

#include <algorithm>
#include <unordered_map>

#include "hapticut/mesh/adjacency.h"

namespace hapticut::cutting {

namespace {
using mesh::edgeKey;

/// Edges with one face, a -> b in that face's winding.
std::vector<LipEdge> boundaryEdges(std::span<const mesh::Face> faces) {
    const mesh::MeshAdjacency adj = mesh::buildAdjacency(faces);
    std::vector<LipEdge> out;
    for (std::uint32_t f = 0; f < faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            if (adj.facesOfEdge(adj.faceEdges[f][k]).size() == 1) out.push_back({faces[f][k], faces[f][(k + 1) % 3]});
    return out;
}
}  // namespace

std::unordered_set<std::uint64_t> rimEdges(std::span<const mesh::Face> faces) {
    std::unordered_set<std::uint64_t> rims;
    for (const LipEdge& e : boundaryEdges(faces)) rims.insert(edgeKey(e.a, e.b));
    return rims;
}

std::vector<LipEdge> lipEdges(std::span<const mesh::Face> faces, const std::unordered_set<std::uint64_t>& rims) {
    std::vector<LipEdge> lips = boundaryEdges(faces);
    std::erase_if(lips, [&](const LipEdge& e) { return rims.count(edgeKey(e.a, e.b)) > 0; });
    return lips;
}

void WoundWalls::setLips(std::span<const LipEdge> lips) {
    lips_.clear();
    lipVertex_.clear();
    faces_.clear();
    std::unordered_map<std::uint32_t, std::uint32_t> index;
    auto wallIndex = [&](std::uint32_t v) {
        const auto [it, added] = index.try_emplace(v, static_cast<std::uint32_t>(lipVertex_.size()));
        if (added) lipVertex_.push_back(v);
        return it->second;
    };
    for (const LipEdge& e : lips) lips_.push_back({wallIndex(e.a), wallIndex(e.b)});
    const auto n = static_cast<std::uint32_t>(lipVertex_.size());
    // Facing into the gap: for a lip a -> b hanging down to feet a', b', the triangles (b, a, a') and
    // (b, a', b') have normal (b - a) x N, the direction across the gap (see update).
    for (const LipEdge& e : lips_) {
        faces_.push_back({e.b, e.a, n + e.a});
        faces_.push_back({e.b, n + e.a, n + e.b});
    }
    positions_.assign(2 * n, Vec3::Zero());
    normals_.assign(2 * n, Vec3::Zero());
    uvs_.assign(2 * n, Vec2::Zero());
    across_.assign(n, Vec3::Zero());
    depth_m_ = 0;
}

void WoundWalls::update(std::span<const Vec3> positions, std::span<const Vec3> vertexNormals,
                        const WallParams& params) {
    if (lips_.empty()) return;
    const std::size_t n = lipVertex_.size();
    double length = 0;
    for (const LipEdge& e : lips_) length += (positions[lipVertex_[e.b]] - positions[lipVertex_[e.a]]).norm();
    depth_m_ = params.depthPerEdge * length / static_cast<double>(lips_.size());

    // Across the gap at each lip vertex: away from its face, in the surface's plane, averaged over its
    // lip edges. With an edge a -> b in its face's winding and outward normal N, (b - a) x N points
    // away from the face.
    std::fill(across_.begin(), across_.end(), Vec3::Zero());
    for (const LipEdge& e : lips_) {
        const std::uint32_t a = lipVertex_[e.a], b = lipVertex_[e.b];
        const Vec3 away = (positions[b] - positions[a]).cross(vertexNormals[a] + vertexNormals[b]);
        across_[e.a] += away;
        across_[e.b] += away;
    }
    // u along the lip: the rest of the surface's texture is no guide inside the wound, and a coordinate
    // along a fixed diagonal runs on smoothly from one lip edge to the next.
    const Vec3 diagonal = Vec3::Ones().normalized();
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t v = lipVertex_[i];
        const Vec3& normal = vertexNormals[v];
        const Vec3 gap = across_[i].norm() > 0 ? Vec3(across_[i].normalized()) : Vec3::Zero();
        positions_[i] = positions[v];
        // Down the wall is -N + lean·gap; the wall's normal, across the gap, is perpendicular to it.
        positions_[n + i] = positions[v] + depth_m_ * (params.lean * gap - normal);
        const Vec3 facing = gap + params.lean * normal;
        normals_[i] = normals_[n + i] = facing.norm() > 0 ? Vec3(facing.normalized()) : normal;
        const double u = positions[v].dot(diagonal) / std::max(depth_m_, 1e-12);
        uvs_[i] = Vec2(u, 0);
        uvs_[n + i] = Vec2(u, 1);
    }
}

}  // namespace hapticut::cutting
