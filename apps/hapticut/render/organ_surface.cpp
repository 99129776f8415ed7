// Render vertices and smooth normals for the deforming, cuttable organ.
#include "render/organ_surface.h"

#include <algorithm>
#include <bit>
#include <unordered_map>

#include "hapticut/mesh/adjacency.h"

namespace hapticut::render {

namespace {
/// The keys (mesh::edgeKey) of the edges that only one of `faces` uses.
std::unordered_set<std::uint64_t> boundaryEdgeKeys(std::span<const mesh::Face> faces) {
    const mesh::MeshAdjacency adj = mesh::buildAdjacency(faces);
    std::unordered_set<std::uint64_t> out;
    for (std::size_t e = 0; e < adj.edges.size(); ++e)
        if (adj.facesOfEdge(e).size() == 1) out.insert(mesh::edgeKey(adj.edges[e][0], adj.edges[e][1]));
    return out;
}
}  // namespace

void OrganSurface::setRims(std::span<const mesh::Face> uncutFaces) { rims_ = boundaryEdgeKeys(uncutFaces); }

void OrganSurface::setTopology(std::span<const mesh::Face> faces, std::span<const mesh::FaceUvs> uvs,
                               std::span<const std::uint8_t> walls, std::size_t vertexCount) {
    faces_.assign(faces.begin(), faces.end());
    walls_.assign(faces.size(), 0);
    std::copy_n(walls.begin(), std::min(walls.size(), faces.size()), walls_.begin());
    source_.clear();
    sourceWall_.clear();
    uv_.clear();
    indices_.clear();
    indices_.reserve(faces.size() * 3);
    normals_.assign(vertexCount, Vec3::Zero());
    wallNormals_.assign(vertexCount, Vec3::Zero());
    // Key: the vertex, its UV as float bits and its material; equal keys share a render vertex.
    struct Key {
        std::uint32_t vertex, u, v;
        std::uint8_t wall;
        bool operator==(const Key&) const = default;
    };
    struct Hash {
        std::size_t operator()(const Key& k) const {
            return (std::size_t{k.vertex} * 0x9E3779B97F4A7C15ull) ^ (std::size_t{k.u} << 21) ^ k.v ^
                   (std::size_t{k.wall} << 62);
        }
    };
    std::unordered_map<Key, std::uint32_t, Hash> index;
    index.reserve(faces.size() * 2);
    lip_.assign(vertexCount, 0);
    std::vector<std::uint8_t> onSurface(vertexCount, 0), onWall(vertexCount, 0);
    for (std::size_t f = 0; f < faces.size(); ++f) {
        const std::uint8_t wall = walls_[f];
        for (std::uint32_t v : faces[f])
            if (v < vertexCount) (wall ? onWall : onSurface)[v] = 1;
        if (wall && !wallsShown_) continue;
        for (int c = 0; c < 3; ++c) {
            const Vec2 uv = f < uvs.size() ? uvs[f][c] : Vec2::Zero();
            const float u = static_cast<float>(uv.x()), v = static_cast<float>(uv.y());
            const Key key{faces[f][c], std::bit_cast<std::uint32_t>(u), std::bit_cast<std::uint32_t>(v), wall};
            auto [it, added] = index.try_emplace(key, static_cast<std::uint32_t>(source_.size()));
            if (added) {
                source_.push_back(faces[f][c]);
                sourceWall_.push_back(wall);
                uv_.push_back(u);
                uv_.push_back(v);
            }
            indices_.push_back(it->second);
        }
    }
    // Lips are drawn darker, like the blood along a fresh wound: where the surface meets a wall, and
    // along an opening left without walls (beyond the organ's own rims).
    for (std::size_t v = 0; v < vertexCount; ++v) lip_[v] = onSurface[v] && onWall[v];
    const mesh::MeshAdjacency adj = mesh::buildAdjacency(faces);
    for (std::size_t e = 0; e < adj.edges.size(); ++e) {
        const auto [a, b] = adj.edges[e];
        if (adj.facesOfEdge(e).size() != 1 || rims_.count(mesh::edgeKey(a, b))) continue;
        if (a < vertexCount) lip_[a] = 1;
        if (b < vertexCount) lip_[b] = 1;
    }
    vertices_.assign(source_.size() * kFloatsPerVertex, 0.0f);
}

void OrganSurface::update(std::span<const Vec3> positions) {
    std::fill(normals_.begin(), normals_.end(), Vec3::Zero());
    std::fill(wallNormals_.begin(), wallNormals_.end(), Vec3::Zero());
    for (std::size_t i = 0; i < faces_.size(); ++i) {
        const mesh::Face& f = faces_[i];
        if (f[0] >= positions.size() || f[1] >= positions.size() || f[2] >= positions.size()) continue;
        // The cross product's length is twice the area: larger faces weigh more.
        const Vec3 n = (positions[f[1]] - positions[f[0]]).cross(positions[f[2]] - positions[f[0]]);
        std::vector<Vec3>& normals = walls_[i] ? wallNormals_ : normals_;
        for (const std::uint32_t v : f) normals[v] += n;
    }
    for (std::vector<Vec3>* normals : {&normals_, &wallNormals_})
        for (Vec3& n : *normals) {
            const double length = n.norm();
            n = length > 0 ? Vec3(n / length) : Vec3::Zero();
        }
    for (std::size_t r = 0; r < source_.size(); ++r) {
        const std::uint32_t v = source_[r];
        const Vec3 p = v < positions.size() ? positions[v] : Vec3::Zero();
        const Vec3& n = sourceWall_[r] ? wallNormals_[v] : normals_[v];
        float* out = &vertices_[r * kFloatsPerVertex];
        for (int i = 0; i < 3; ++i) {
            out[i] = static_cast<float>(p[i]);
            out[3 + i] = static_cast<float>(n[i]);
        }
        out[6] = uv_[2 * r];
        out[7] = uv_[2 * r + 1];
        out[8] = sourceWall_[r] ? 2.0f : lip_[v] ? 1.0f : 0.0f;  // 2: the wall's own material
    }
}

}  // namespace hapticut::render
