// Procedural heart. The surface is star-shaped about its centre: r(d) is a smooth maximum (p-norm) of
// the exit distances of anatomical ellipsoids that all contain the centre, so the surface is closed and
// single-valued along every ray and r(d) is closed-form at any resolution. It is meshed by projecting a
// box-surface grid of a x b x c cells (4(ab + bc + ca) triangles, so any count is reachable within 2%)
// and relaxed by Laplacian smoothing with re-projection, which evens out the triangles.
#include "hapticut/mesh/procedural/heart.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include <Eigen/Geometry>

#include "hapticut/geometry/aabb.h"
#include "hapticut/mesh/edge_flip.h"
#include "hapticut/mesh/uv_projection.h"

namespace hapticut::mesh::procedural {

namespace {

struct Ellipsoid {
    Vec3 centre, radii;
    Eigen::Matrix3d toLocal;  // rotation from the heart frame into the ellipsoid's axes
};

Ellipsoid ellipsoid(Vec3 centre, Vec3 radii, Vec3 long_axis) {
    // Rotate the ellipsoid's y axis onto long_axis.
    const Eigen::Matrix3d r =
        Eigen::Quaterniond::FromTwoVectors(Vec3::UnitY(), long_axis.normalized()).toRotationMatrix();
    return {centre, radii, r.transpose()};
}

// Heart frame: +y toward the base (great vessels), -y the apex, +z anterior, +x the patient's left.
const std::array<Ellipsoid, 7>& parts() {
    static const std::array<Ellipsoid, 7> p = {
        ellipsoid({0.10, -0.12, -0.02}, {0.40, 0.66, 0.38}, {-0.30, 1.0, -0.10}),  // left ventricle, forms the apex
        ellipsoid({-0.14, -0.02, 0.10}, {0.36, 0.50, 0.32}, {-0.15, 1.0, 0.05}),   // right ventricle, front right
        ellipsoid({0.14, 0.30, -0.18}, {0.30, 0.24, 0.26}, {0.3, 1.0, 0.0}),       // left atrium, back
        ellipsoid({-0.30, 0.24, -0.06}, {0.28, 0.30, 0.27}, {-0.2, 1.0, 0.0}),     // right atrium
        ellipsoid({-0.03, 0.34, -0.02}, {0.15, 0.58, 0.15}, {-0.15, 1.0, 0.0}),    // aorta
        ellipsoid({0.07, 0.31, 0.08}, {0.14, 0.52, 0.14}, {0.35, 1.0, 0.25}),      // pulmonary trunk
        ellipsoid({-0.20, 0.24, -0.04}, {0.12, 0.52, 0.12}, {-0.3, 1.0, -0.25}),   // superior vena cava
    };
    return p;
}

/// Distance along unit d from the origin to where the ray leaves the ellipsoid (it contains the origin).
double exitDistance(const Ellipsoid& e, const Vec3& d) {
    const Vec3 o = (e.toLocal * (-e.centre)).cwiseQuotient(e.radii);
    const Vec3 v = (e.toLocal * d).cwiseQuotient(e.radii);
    const double a = v.squaredNorm(), b = o.dot(v), c = o.squaredNorm() - 1;  // c < 0: origin inside
    return (-b + std::sqrt(std::max(b * b - a * c, 0.0))) / a;
}

struct Grid {
    int a = 1, b = 1, c = 1;
};

/// Box cells a x b x c (along x, y, z) with 4(ab + bc + ca) closest to the target, shaped like the heart.
Grid chooseGrid(int triangles) {
    const double rx = 0.80, rz = 0.72;  // heart width and depth relative to its length
    Grid best;
    double bestScore = 1e300;
    for (int b = 1; b <= 2000; ++b) {
        const int a0 = std::max(1, static_cast<int>(std::lround(b * rx))),
                  c0 = std::max(1, static_cast<int>(std::lround(b * rz)));
        for (int a = std::max(1, a0 - 2); a <= a0 + 2; ++a)
            for (int c = std::max(1, c0 - 2); c <= c0 + 2; ++c) {
                const double f = 4.0 * (a * b + b * c + c * a);
                const double countError = std::abs(f - triangles) / triangles;
                const double shapeError = std::abs(double(a) / b - rx) + std::abs(double(c) / b - rz);
                const double score = countError + 0.01 * shapeError;
                if (score < bestScore) bestScore = score, best = {a, b, c};
            }
        if (4.0 * (b * b * (rx + rz + rx * rz)) > 1.5 * triangles + 100) break;
    }
    return best;
}

Vec3 projectToSurface(const Vec3& p) {
    const double n = p.norm();
    const Vec3 d = n > 0 ? Vec3(p / n) : Vec3::UnitY();
    return heartRadius(d) * d;
}

}  // namespace

double heartRadius(const Vec3& d) {
    constexpr double kBlend = 6;  // p-norm exponent: larger is a sharper union, smaller a softer blend
    double sum = 0;
    for (const Ellipsoid& e : parts()) sum += std::pow(exitDistance(e, d), kBlend);
    return std::pow(sum, 1 / kBlend);
}

SurfaceMesh makeHeart(const HeartOptions& options) {
    const Grid g = chooseGrid(std::max(options.triangles, 12));
    const std::array<int, 3> cells = {g.a, g.b, g.c};

    // Vertices: integer lattice points on the box surface, shared along box edges through the map.
    SurfaceMesh mesh;
    std::unordered_map<std::uint64_t, std::uint32_t> ids;
    ids.reserve(static_cast<std::size_t>(2 * (g.a * g.b + g.b * g.c + g.c * g.a) + 8));
    const Vec3 shape(0.80, 1.0, 0.72);
    auto vertex = [&](std::array<int, 3> q) {
        const std::uint64_t key = (std::uint64_t(q[0]) * 4096 + std::uint64_t(q[1])) * 4096 + std::uint64_t(q[2]);
        auto [it, inserted] = ids.try_emplace(key, static_cast<std::uint32_t>(mesh.positions.size()));
        if (inserted) {
            // Equal-angle warp (tan) spreads points evenly over the sphere of directions.
            Vec3 dir;
            for (int k = 0; k < 3; ++k)
                dir[k] = shape[k] * std::tan((2.0 * q[k] / cells[k] - 1.0) * std::numbers::pi / 4);
            mesh.positions.push_back(projectToSurface(dir));
        }
        return it->second;
    };

    // Faces: each box side is a grid of quads, split along the shorter diagonal of the projected quad.
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            for (int i = 0; i < cells[u]; ++i)
                for (int j = 0; j < cells[v]; ++j) {
                    std::array<std::uint32_t, 4> quad;
                    const int corner[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
                    for (int k = 0; k < 4; ++k) {
                        std::array<int, 3> q{};
                        q[axis] = side * cells[axis];
                        q[u] = corner[k][0];
                        q[v] = corner[k][1];
                        quad[k] = vertex(q);
                    }
                    if (side == 0) std::swap(quad[1], quad[3]);  // keep every face counter-clockwise from outside
                    const auto& p = mesh.positions;
                    if ((p[quad[0]] - p[quad[2]]).squaredNorm() <= (p[quad[1]] - p[quad[3]]).squaredNorm()) {
                        mesh.faces.push_back({quad[0], quad[1], quad[2]});
                        mesh.faces.push_back({quad[0], quad[2], quad[3]});
                    } else {
                        mesh.faces.push_back({quad[0], quad[1], quad[3]});
                        mesh.faces.push_back({quad[1], quad[2], quad[3]});
                    }
                }
        }

    // Smoothing with re-projection moves each vertex toward the area-weighted mean of its faces'
    // centroids and back onto the surface along its ray. Weighting by area evens out triangle areas,
    // and so the lumped node masses that set the stable time step; the plain neighbour mean shrinks
    // the rings of low-valence vertices instead. Edge flips between rounds remove the slivers
    // smoothing alone leaves where the thin vessels join the body.
    const std::size_t n = mesh.positions.size();
    std::vector<Vec3> next(n), weighted(n);
    std::vector<double> weight(n);
    constexpr int kRounds = 3;
    for (int round = 0; round < kRounds; ++round) {
        const int iterations = (options.smoothingIterations + kRounds - 1) / kRounds;
        for (int it = 0; it < iterations; ++it) {
            std::fill(weighted.begin(), weighted.end(), Vec3::Zero());
            std::fill(weight.begin(), weight.end(), 0.0);
            for (const Face& f : mesh.faces) {
                const Vec3 &a = mesh.positions[f[0]], &b = mesh.positions[f[1]], &c = mesh.positions[f[2]];
                const double area = 0.5 * (b - a).cross(c - a).norm();
                const Vec3 centroid = (a + b + c) / 3;
                for (std::uint32_t v : f) weighted[v] += area * centroid, weight[v] += area;
            }
            for (std::size_t i = 0; i < n; ++i) next[i] = projectToSurface(weighted[i] / weight[i]);
            mesh.positions.swap(next);
        }
        improveByEdgeFlips(mesh, FlipOptions{.maxPasses = 4, .minNormalCosine = 0.7});
    }

    // Scale to the requested length and centre the bounding box at the origin.
    const geometry::Aabb box = geometry::boundsOf(mesh.positions);
    const double scale = options.length_m / box.extent().y();
    const Vec3 centre = box.center();
    for (Vec3& p : mesh.positions) p = (p - centre) * scale;
    // Spherical UVs about the generator's centre (where the rays started), now at -centre * scale.
    sphericalUvs(mesh, -centre * scale);
    computeFaceNormals(mesh);
    return mesh;
}

}  // namespace hapticut::mesh::procedural
