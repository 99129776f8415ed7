// Render vertices and smooth normals for the deforming, cuttable organ.
#include "render/organ_surface.h"

#include <algorithm>
#include <bit>
#include <unordered_map>

namespace hapticut::render {

void OrganSurface::setTopology(std::span<const mesh::Face> faces, std::span<const mesh::FaceUvs> uvs,
                               std::size_t vertexCount) {
    faces_.assign(faces.begin(), faces.end());
    source_.clear();
    uv_.clear();
    indices_.clear();
    indices_.reserve(faces.size() * 3);
    normals_.assign(vertexCount, Vec3::Zero());
    // Key: the vertex and its UV as float bits; equal UVs on one vertex share a render vertex.
    struct Key {
        std::uint32_t vertex, u, v;
        bool operator==(const Key&) const = default;
    };
    struct Hash {
        std::size_t operator()(const Key& k) const {
            return (std::size_t{k.vertex} * 0x9E3779B97F4A7C15ull) ^ (std::size_t{k.u} << 21) ^ k.v;
        }
    };
    std::unordered_map<Key, std::uint32_t, Hash> index;
    index.reserve(faces.size() * 2);
    for (std::size_t f = 0; f < faces.size(); ++f)
        for (int c = 0; c < 3; ++c) {
            const Vec2 uv = f < uvs.size() ? uvs[f][c] : Vec2::Zero();
            const float u = static_cast<float>(uv.x()), v = static_cast<float>(uv.y());
            const Key key{faces[f][c], std::bit_cast<std::uint32_t>(u), std::bit_cast<std::uint32_t>(v)};
            auto [it, added] = index.try_emplace(key, static_cast<std::uint32_t>(source_.size()));
            if (added) {
                source_.push_back(faces[f][c]);
                uv_.push_back(u);
                uv_.push_back(v);
            }
            indices_.push_back(it->second);
        }
    // Lips: the ends of edges a cut opened (edges only one face uses, beyond the organ's own rims).
    // Drawn darker, like the blood along a fresh wound, with walls hanging into the gap.
    const std::vector<cutting::LipEdge> lips = cutting::lipEdges(faces, rims_);
    lip_.assign(vertexCount, 0);
    for (const cutting::LipEdge& e : lips) {
        if (e.a < vertexCount) lip_[e.a] = 1;
        if (e.b < vertexCount) lip_[e.b] = 1;
    }
    walls_.setLips(wallsShown_ ? std::span<const cutting::LipEdge>(lips) : std::span<const cutting::LipEdge>());
    const auto organVertices = static_cast<std::uint32_t>(source_.size());
    for (const mesh::Face& f : walls_.faces())
        for (std::uint32_t v : f) indices_.push_back(organVertices + v);
    vertices_.assign((source_.size() + walls_.positions().size()) * kFloatsPerVertex, 0.0f);
}

void OrganSurface::update(std::span<const Vec3> positions) {
    std::fill(normals_.begin(), normals_.end(), Vec3::Zero());
    for (const mesh::Face& f : faces_) {
        if (f[0] >= positions.size() || f[1] >= positions.size() || f[2] >= positions.size()) continue;
        // The cross product's length is twice the area: larger faces weigh more.
        const Vec3 n = (positions[f[1]] - positions[f[0]]).cross(positions[f[2]] - positions[f[0]]);
        for (const std::uint32_t v : f) normals_[v] += n;
    }
    for (Vec3& n : normals_) {
        const double length = n.norm();
        n = length > 0 ? Vec3(n / length) : Vec3::Zero();
    }
    for (std::size_t r = 0; r < source_.size(); ++r) {
        const std::uint32_t v = source_[r];
        const Vec3 p = v < positions.size() ? positions[v] : Vec3::Zero();
        float* out = &vertices_[r * kFloatsPerVertex];
        for (int i = 0; i < 3; ++i) {
            out[i] = static_cast<float>(p[i]);
            out[3 + i] = static_cast<float>(normals_[v][i]);
        }
        out[6] = uv_[2 * r];
        out[7] = uv_[2 * r + 1];
        out[8] = lip_[v] ? 1.0f : 0.0f;
    }
    if (walls_.empty()) return;
    walls_.update(positions, normals_);
    const std::span<const Vec3> wall = walls_.positions(), wallNormals = walls_.normals();
    const std::span<const Vec2> wallUvs = walls_.uvs();
    for (std::size_t i = 0; i < wall.size(); ++i) {
        float* out = &vertices_[(source_.size() + i) * kFloatsPerVertex];
        for (int k = 0; k < 3; ++k) {
            out[k] = static_cast<float>(wall[i][k]);
            out[3 + k] = static_cast<float>(wallNormals[i][k]);
        }
        out[6] = static_cast<float>(wallUvs[i].x());
        out[7] = static_cast<float>(wallUvs[i].y());
        out[8] = 2.0f;  // the wall's own material
    }
}

}  // namespace hapticut::render
