// Marching tetrahedra over a regular grid (Doi & Koide 1991, "An efficient method of triangulating
// equi-valued surfaces by using tetrahedral cells").
#include "hapticut/mesh/procedural/implicit_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace hapticut::mesh::procedural {

namespace {

/// The six tetrahedra of a cube, by corner (bit 0: +x, bit 1: +y, bit 2: +z): each walks from corner 0 to
/// corner 7 along the axes in one order, so all six share the main diagonal and a neighbouring cube
/// splits the face between them along the same diagonal.
constexpr std::array<std::array<int, 4>, 6> kKuhnTetrahedra = {{
    {0, 1, 3, 7},
    {0, 1, 5, 7},
    {0, 2, 3, 7},
    {0, 2, 6, 7},
    {0, 4, 5, 7},
    {0, 4, 6, 7},
}};

class Polygoniser {
public:
    Polygoniser(const ImplicitField& field, const geometry::Aabb& box, double cell_m)
        : origin_(box.min), cell_(cell_m) {
        const Vec3 cells = (box.extent() / cell_m).array().ceil().max(1.0);
        n_ = {static_cast<int>(cells.x()), static_cast<int>(cells.y()), static_cast<int>(cells.z())};
        values_.resize(static_cast<std::size_t>(n_[0] + 1) * (n_[1] + 1) * (n_[2] + 1));
        for (int k = 0; k <= n_[2]; ++k)
            for (int j = 0; j <= n_[1]; ++j)
                for (int i = 0; i <= n_[0]; ++i) {
                    double v = field(corner(i, j, k));
                    // A corner exactly on the surface would give a triangle of no area; nudged outside it
                    // gives a tiny one. The outer layer is outside whatever the field says, which closes
                    // the surface of a shape that pokes out of the box.
                    const bool outer = i == 0 || j == 0 || k == 0 || i == n_[0] || j == n_[1] || k == n_[2];
                    if (!(v != 0) || outer) v = std::max(std::isfinite(v) ? v : cell_m, 1e-12);
                    values_[index(i, j, k)] = v;
                }
    }

    SurfaceMesh run() {
        for (int k = 0; k < n_[2]; ++k)
            for (int j = 0; j < n_[1]; ++j)
                for (int i = 0; i < n_[0]; ++i) cube(i, j, k);
        return std::move(mesh_);
    }

private:
    Vec3 corner(int i, int j, int k) const { return origin_ + cell_ * Vec3(i, j, k); }
    std::size_t index(int i, int j, int k) const {
        return (static_cast<std::size_t>(k) * (n_[1] + 1) + j) * (n_[0] + 1) + i;
    }

    void cube(int i, int j, int k) {
        std::array<std::size_t, 8> id;
        std::array<Vec3, 8> at;
        for (int c = 0; c < 8; ++c) {
            const int ci = i + (c & 1), cj = j + ((c >> 1) & 1), ck = k + ((c >> 2) & 1);
            id[c] = index(ci, cj, ck);
            at[c] = corner(ci, cj, ck);
        }
        for (const auto& tet : kKuhnTetrahedra) {
            std::array<std::size_t, 4> g;
            std::array<Vec3, 4> p;
            for (int c = 0; c < 4; ++c) g[c] = id[tet[c]], p[c] = at[tet[c]];
            tetrahedron(g, p);
        }
    }

    void tetrahedron(const std::array<std::size_t, 4>& g, const std::array<Vec3, 4>& p) {
        std::array<int, 4> inside, outside;
        int in = 0, out = 0;
        for (int c = 0; c < 4; ++c) (values_[g[c]] < 0 ? inside[in++] : outside[out++]) = c;
        if (in == 0 || out == 0) return;
        Vec3 inCentre = Vec3::Zero(), outCentre = Vec3::Zero();
        for (int c = 0; c < in; ++c) inCentre += p[inside[c]] / in;
        for (int c = 0; c < out; ++c) outCentre += p[outside[c]] / out;
        const Vec3 outward = outCentre - inCentre;
        const auto crossing = [&](int a, int b) { return edgeVertex(g[a], g[b], p[a], p[b]); };
        if (in == 1 || out == 1) {  // one corner cut off: a triangle
            const int lone = in == 1 ? inside[0] : outside[0];
            std::array<std::uint32_t, 3> t;
            for (int c = 0, n = 0; c < 4; ++c)
                if (c != lone) t[n++] = crossing(lone, c);
            triangle(t, outward);
            return;
        }
        // Two corners on each side: a quad through the four crossed edges, in the order they go round.
        const int a = inside[0], b = inside[1], c = outside[0], d = outside[1];
        const std::uint32_t ac = crossing(a, c), ad = crossing(a, d), bd = crossing(b, d), bc = crossing(b, c);
        triangle({ac, ad, bd}, outward);
        triangle({ac, bd, bc}, outward);
    }

    void triangle(std::array<std::uint32_t, 3> t, const Vec3& outward) {
        const Vec3 &a = mesh_.positions[t[0]], &b = mesh_.positions[t[1]], &c = mesh_.positions[t[2]];
        if ((b - a).cross(c - a).dot(outward) < 0) std::swap(t[1], t[2]);
        mesh_.faces.push_back(t);
    }

    /// The surface's vertex on the grid edge (a, b), shared by every tetrahedron that has that edge.
    std::uint32_t edgeVertex(std::size_t a, std::size_t b, const Vec3& pa, const Vec3& pb) {
        const std::uint64_t key = a < b ? a * values_.size() + b : b * values_.size() + a;
        const auto [it, added] = vertexOfEdge_.try_emplace(key, static_cast<std::uint32_t>(mesh_.positions.size()));
        if (added) {
            // Linear interpolation, kept 2% away from either end: a corner on the surface would put
            // several edges' vertices on one point, and those faces would have no area.
            const double t = std::clamp(values_[a] / (values_[a] - values_[b]), 0.02, 0.98);
            mesh_.positions.push_back(pa + t * (pb - pa));
        }
        return it->second;
    }

    Vec3 origin_;
    double cell_;
    std::array<int, 3> n_{};
    std::vector<double> values_;
    std::unordered_map<std::uint64_t, std::uint32_t> vertexOfEdge_;
    SurfaceMesh mesh_;
};

}  // namespace

SurfaceMesh polygonise(const ImplicitField& field, const geometry::Aabb& box, double cell_m) {
    return Polygoniser(field, box, cell_m).run();
}

}  // namespace hapticut::mesh::procedural
