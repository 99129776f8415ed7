// Render vertices and smooth normals for the deforming, cuttable organ.
#include "render/organ_surface.h"

#include <algorithm>
#include <bit>
#include <unordered_map>

namespace hapticut::render {

void OrganSurface::setTopology(std::span<const mesh::Face> faces, std::span<const mesh::FaceUvs> uvs, std::size_t vertexCount) {
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
        std::size_t operator()(const Key& k) const { return (std::size_t{k.vertex} * 0x9E3779B97F4A7C15ull) ^ (std::size_t{k.u} << 21) ^ k.v; }
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
    // Lips: the ends of edges only one face uses. Drawn darker, like the blood along a fresh wound.
    lip_.assign(vertexCount, 0);
    std::unordered_map<std::uint64_t, int> edgeUses;
    edgeUses.reserve(faces.size() * 2);
    for (const mesh::Face& f : faces)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = std::min(f[c], f[(c + 1) % 3]), b = std::max(f[c], f[(c + 1) % 3]);
            ++edgeUses[(std::uint64_t{a} << 32) | b];
        }
    for (const auto& [key, uses] : edgeUses)
        if (uses == 1) {
            const auto a = static_cast<std::uint32_t>(key >> 32), b = static_cast<std::uint32_t>(key & 0xffffffffu);
            if (a < vertexCount) lip_[a] = 1;
            if (b < vertexCount) lip_[b] = 1;
        }
    vertices_.assign(source_.size() * kFloatsPerVertex, 0.0f);
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
}

}  // namespace hapticut::render
