// Spherical texture coordinates.
#include "hapticut/mesh/uv_projection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace hapticut::mesh {

void sphericalUvs(SurfaceMesh& mesh, const Vec3& centre) {
    mesh.uvs.resize(mesh.faces.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        std::array<Vec3, 3> d;
        std::array<double, 3> u{};
        std::array<bool, 3> pole{};
        for (int k = 0; k < 3; ++k) {
            const Vec3 r = mesh.positions[mesh.faces[f][k]] - centre;
            d[k] = r.norm() > 0 ? Vec3(r.normalized()) : Vec3::UnitY();
            pole[k] = std::hypot(d[k].x(), d[k].z()) < 1e-9;
            u[k] = 0.5 + std::atan2(d[k].x(), d[k].z()) / (2 * std::numbers::pi);
        }
        double lo = 2, hi = -1;
        for (int k = 0; k < 3; ++k)
            if (!pole[k]) lo = std::min(lo, u[k]), hi = std::max(hi, u[k]);
        for (int k = 0; k < 3; ++k)
            if (!pole[k] && hi - lo > 0.5 && u[k] < 0.5) u[k] += 1;
        for (int k = 0; k < 3; ++k)
            if (pole[k]) {
                double sum = 0;
                int count = 0;
                for (int j = 0; j < 3; ++j)
                    if (!pole[j]) sum += u[j], ++count;
                u[k] = count ? sum / count : 0.5;
            }
        for (int k = 0; k < 3; ++k)
            mesh.uvs[f][k] = Vec2(u[k], 0.5 + std::asin(std::clamp(d[k].y(), -1.0, 1.0)) / std::numbers::pi);
    }
}

}  // namespace hapticut::mesh
