// Closed primitive meshes and mesh concatenation.
#include "hapticut/mesh/procedural/primitives.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace hapticut::mesh::procedural {

namespace {
/// Fills planar UVs (x, y scaled into [0, 1] over the bounding square), normals and edges.
void finish(SurfaceMesh& m) {
    m.uvs.clear();
    for (const Face& f : m.faces) {
        FaceUvs uv;
        for (int k = 0; k < 3; ++k)
            uv[k] = Vec2(0.5 + 0.5 * std::atan2(m.positions[f[k]].y(), m.positions[f[k]].x()) / std::numbers::pi,
                         m.positions[f[k]].z());
        m.uvs.push_back(uv);
    }
    computeFaceNormals(m);
    m.edges = edgesOfFaces(m.faces);
}
}  // namespace

SurfaceMesh makeCylinder(const Vec3& base, const Vec3& axis, double radius_m, double length_m, int segments) {
    const Eigen::Matrix3d r = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis.normalized()).toRotationMatrix();
    SurfaceMesh m;
    const auto s = static_cast<std::uint32_t>(segments);
    for (int ring = 0; ring < 2; ++ring)
        for (int i = 0; i < segments; ++i) {
            const double t = 2 * std::numbers::pi * i / segments;
            m.positions.push_back(base + r * Vec3(radius_m * std::cos(t), radius_m * std::sin(t), ring * length_m));
        }
    const auto c0 = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(base);
    m.positions.push_back(base + r * Vec3(0, 0, length_m));
    for (std::uint32_t i = 0; i < s; ++i) {
        const std::uint32_t j = (i + 1) % s;
        m.faces.push_back({i, j, s + j});
        m.faces.push_back({i, s + j, s + i});
        m.faces.push_back({c0, j, i});
        m.faces.push_back({c0 + 1, s + i, s + j});
    }
    finish(m);
    return m;
}

SurfaceMesh makeSphere(const Vec3& centre, double radius_m, int segments, int rings) {
    SurfaceMesh m;
    m.positions.push_back(centre - Vec3(0, 0, radius_m));
    for (int ring = 1; ring < rings; ++ring) {
        const double phi = std::numbers::pi * ring / rings;
        for (int i = 0; i < segments; ++i) {
            const double t = 2 * std::numbers::pi * i / segments;
            m.positions.push_back(
                centre + radius_m * Vec3(std::sin(phi) * std::cos(t), std::sin(phi) * std::sin(t), -std::cos(phi)));
        }
    }
    m.positions.push_back(centre + Vec3(0, 0, radius_m));
    const auto s = static_cast<std::uint32_t>(segments);
    const auto top = static_cast<std::uint32_t>(m.positions.size() - 1);
    auto at = [&](int ring, std::uint32_t i) { return 1 + static_cast<std::uint32_t>(ring - 1) * s + i % s; };
    for (std::uint32_t i = 0; i < s; ++i) {
        m.faces.push_back({0, at(1, i + 1), at(1, i)});
        m.faces.push_back({top, at(rings - 1, i), at(rings - 1, i + 1)});
        for (int ring = 1; ring + 1 < rings; ++ring) {
            m.faces.push_back({at(ring, i), at(ring, i + 1), at(ring + 1, i + 1)});
            m.faces.push_back({at(ring, i), at(ring + 1, i + 1), at(ring + 1, i)});
        }
    }
    finish(m);
    return m;
}

SurfaceMesh makePrism(std::span<const Vec2> polygon, double z0_m, double z1_m) {
    SurfaceMesh m;
    const auto n = static_cast<std::uint32_t>(polygon.size());
    for (double z : {z0_m, z1_m})
        for (const Vec2& p : polygon) m.positions.emplace_back(p.x(), p.y(), z);
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t j = (i + 1) % n;
        m.faces.push_back({i, j, n + j});
        m.faces.push_back({i, n + j, n + i});
    }
    for (std::uint32_t i = 1; i + 1 < n; ++i) {
        m.faces.push_back({0, i + 1, i});          // bottom, facing -z
        m.faces.push_back({n, n + i, n + i + 1});  // top, facing +z
    }
    finish(m);
    return m;
}

SurfaceMesh makeGrid(int n, double spacing_m) {
    SurfaceMesh m;
    const auto row = static_cast<std::uint32_t>(n + 1);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            m.positions.emplace_back((i - 0.5 * n) * spacing_m, (j - 0.5 * n) * spacing_m, 0.0);
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(n); ++j)
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
            const std::uint32_t v = j * row + i;
            m.faces.push_back({v, v + 1, v + row + 1});
            m.faces.push_back({v, v + row + 1, v + row});
        }
    finish(m);
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            m.uvs[f][k] = m.positions[m.faces[f][k]].head<2>() / (n * spacing_m) + Vec2(0.5, 0.5);
    return m;
}

void appendMesh(SurfaceMesh& a, const SurfaceMesh& b) {
    const auto offset = static_cast<std::uint32_t>(a.positions.size());
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    for (const Face& f : b.faces) a.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
    for (const Edge& e : b.edges) a.edges.push_back({e[0] + offset, e[1] + offset});
    a.uvs.insert(a.uvs.end(), b.uvs.begin(), b.uvs.end());
    a.normals.insert(a.normals.end(), b.normals.begin(), b.normals.end());
}

}  // namespace hapticut::mesh::procedural
