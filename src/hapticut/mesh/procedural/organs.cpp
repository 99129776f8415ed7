// Procedural liver and kidney. Each shape is an implicit field in centimetres built from ellipsoids
// (Quilez's first-order distance estimate) joined and carved with polynomial smooth minima, so lobes
// blend and hollows are rounded; `polygonise` turns each part into a closed surface.
#include "hapticut/mesh/procedural/organs.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "hapticut/mesh/procedural/implicit_surface.h"

namespace hapticut::mesh::procedural {

namespace {

constexpr double kCm = 0.01;

/// About the distance (cm) from q, in the ellipsoid's own frame, to an ellipsoid of these radii.
double ellipsoid(const Vec3& q, const Vec3& radii) {
    const double k0 = q.cwiseQuotient(radii).norm(), k1 = q.cwiseQuotient(radii.cwiseProduct(radii)).norm();
    return k1 > 0 ? k0 * (k0 - 1) / k1 : -radii.minCoeff();
}

double smoothMin(double a, double b, double k) {
    const double h = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - 0.25 * h * h * k;
}

double smoothMax(double a, double b, double k) { return -smoothMin(-a, -b, k); }

/// q (cm) in the frame of a shape centred at `centre` and turned by `angle_deg` about `axis`.
Vec3 toFrame(const Vec3& q, const Vec3& centre, double angle_deg, const Vec3& axis) {
    return Eigen::AngleAxisd(-angle_deg * std::numbers::pi / 180, axis.normalized()) * (q - centre);
}

// The gallbladder lies under the right lobe, its fundus toward the front and down.
double gallbladder(const Vec3& q) {
    return ellipsoid(toFrame(q, Vec3(-1.8, -5.6, 2.8), -35, Vec3::UnitX()), Vec3(1.5, 1.5, 4));
}

double liver(const Vec3& q) {
    const double right = ellipsoid(q - Vec3(-3.5, 0.5, 0), Vec3(8, 7.5, 7));
    Vec3 l = q - Vec3(5.5, 2.5, 1.5);
    l.y() /= 1 - 0.04 * std::max(l.x(), 0.0);  // the left lobe thins toward its tip
    double shape = smoothMin(right, ellipsoid(l, Vec3(7.5, 3.2, 5)), 4);
    // The visceral surface faces down and back, flattened against the bowel and the right kidney.
    shape = smoothMax(shape, (-(q.y() + 3.5) - 0.5 * q.z()) / std::sqrt(1.25), 2);
    shape = smoothMax(shape, 1.6 - (q - Vec3(1.5, -1.5, 6.5)).norm(), 1);  // the round ligament's notch
    return smoothMax(shape, 0.4 - gallbladder(q), 1);                      // the gallbladder's fossa, 4 mm clear
}

double kidney(const Vec3& q) {
    // Bent about its long axis so the medial side (+x) is concave, with the hilum in its middle.
    const double body = ellipsoid(Vec3(q.x() + 0.035 * q.y() * q.y(), q.y(), q.z()), Vec3(3, 5.5, 2));
    return smoothMax(body, 1.7 - (q - Vec3(3.1, 0, 0)).norm(), 1);
}

double adrenalGland(const Vec3& q) {
    return ellipsoid(toFrame(q, Vec3(-1.0, 6.9, -0.2), -15, Vec3::UnitZ()), Vec3(2.2, 1.0, 0.7));
}

/// Polygonises each part of a shape in centimetres over `box_cm` and joins them as named parts, centred.
SurfaceMesh segment(std::initializer_list<std::pair<const char*, double (*)(const Vec3&)>> parts,
                    const geometry::Aabb& box_cm, double cell_m) {
    const geometry::Aabb box{box_cm.min * kCm, box_cm.max * kCm};
    SurfaceMesh organ;
    for (const auto& named : parts) {
        // Named, not a structured binding: clang 14 (the fuzzers' build) cannot capture one in a lambda.
        double (*const field)(const Vec3&) = named.second;
        const SurfaceMesh part = polygonise([field](const Vec3& p) { return field(p / kCm); }, box, cell_m);
        const auto offset = static_cast<std::uint32_t>(organ.positions.size());
        organ.positions.insert(organ.positions.end(), part.positions.begin(), part.positions.end());
        for (const Face& f : part.faces) organ.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
        organ.faceParts.resize(organ.faces.size(), static_cast<std::uint32_t>(organ.partNames.size()));
        organ.partNames.emplace_back(named.first);
    }
    const Vec3 centre = geometry::boundsOf(organ.positions).center();
    for (Vec3& p : organ.positions) p -= centre;
    return organ;
}

}  // namespace

SurfaceMesh segmentLiver(double cell_m) {
    return segment({{"liver", liver}, {"gallbladder", gallbladder}}, {Vec3(-13, -11, -9), Vec3(15, 10, 10)}, cell_m);
}

SurfaceMesh segmentKidney(double cell_m) {
    return segment({{"kidney", kidney}, {"adrenal gland", adrenalGland}}, {Vec3(-5, -7, -3), Vec3(5, 9, 3)}, cell_m);
}

Result<ReadyOrgan, std::string> makeSimulationReady(SurfaceMesh segmented, std::size_t triangles) {
    ReadyOrgan organ;
    RepairOptions repair;
    repair.repair = true;
    organ.repair = cleanMesh(segmented, repair);
    RemeshOptions remesh;
    remesh.targetEdge_m = targetEdgeForTriangles(segmented, triangles);
    remesh.targetTriangles = triangles;
    auto remeshed = remeshIsotropic(segmented, remesh);
    if (!remeshed) return unexpected(remeshed.error());
    organ.remesh = std::move(*remeshed);
    organ.mesh = std::move(organ.remesh.mesh);
    return organ;
}

}  // namespace hapticut::mesh::procedural
