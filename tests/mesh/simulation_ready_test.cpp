// A segmentation made simulation-ready: parts touching at non-manifold edges, an inward part, duplicate
// and degenerate faces, slivers and body coordinates, repaired and remeshed into even, closed, outward
// pieces on the same surface.
#include <gtest/gtest.h>

#include <map>
#include <numeric>

#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/mesh/remesh.h"
#include "hapticut/mesh/repair.h"
#include "test_support.h"

namespace hapticut::mesh {
namespace {

/// The pieces of a mesh: faces joined across shared edges, each piece its faces.
std::vector<std::vector<std::uint32_t>> piecesOf(const SurfaceMesh& m) {
    std::vector<std::uint32_t> parent(m.faces.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](std::uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    std::map<std::uint64_t, std::uint32_t> firstFace;
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            if (const auto [it, fresh] = firstFace.emplace(edgeKey(m.faces[f][k], m.faces[f][(k + 1) % 3]), f); !fresh)
                parent[root(f)] = root(it->second);
    std::map<std::uint32_t, std::vector<std::uint32_t>> pieces;
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) pieces[root(f)].push_back(f);
    std::vector<std::vector<std::uint32_t>> out;
    for (auto& [r, faces] : pieces) out.push_back(std::move(faces));
    return out;
}

double signedVolumeOf(const SurfaceMesh& m, const std::vector<std::uint32_t>& faces) {
    double v = 0;
    for (std::uint32_t f : faces)
        v += m.positions[m.faces[f][0]].dot(m.positions[m.faces[f][1]].cross(m.positions[m.faces[f][2]])) / 6;
    return v;
}

/// Two UV spheres (slivers at their poles) touching along one edge, in body coordinates half a metre
/// from the origin: the second is the first mirrored across a plane that holds one of its equator's
/// edges and touches it only there (the plane's normal is the mean of that edge's two face normals).
/// The second is inside out; a face of each is written twice, and two faces are degenerate.
SurfaceMesh touchingSpheres(Vec3& centreA, Vec3& centreB, double& radius) {
    radius = 0.03;
    centreA = Vec3(0.31, -0.42, 0.18);
    SurfaceMesh a = procedural::makeSphere(centreA, radius, 24, 16);
    // The equator's edge: the one whose midpoint lies farthest along +x.
    std::array<std::uint32_t, 2> edge{};
    double best = -1e9;
    Vec3 normal = Vec3::Zero();
    std::map<std::uint64_t, std::vector<std::uint32_t>> facesOfEdge;
    for (std::uint32_t f = 0; f < a.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) facesOfEdge[edgeKey(a.faces[f][k], a.faces[f][(k + 1) % 3])].push_back(f);
    for (const auto& [key, faces] : facesOfEdge) {
        const auto u = static_cast<std::uint32_t>(key >> 32), v = static_cast<std::uint32_t>(key & 0xffffffffu);
        const Vec3 mid = 0.5 * (a.positions[u] + a.positions[v]);
        if (mid.x() <= best) continue;
        best = mid.x();
        edge = {u, v};
        normal = Vec3::Zero();
        for (std::uint32_t f : faces) {
            const Face& g = a.faces[f];
            normal += (a.positions[g[1]] - a.positions[g[0]]).cross(a.positions[g[2]] - a.positions[g[0]]).normalized();
        }
    }
    normal.normalize();
    const Vec3 onPlane = a.positions[edge[0]];
    SurfaceMesh b = a;
    for (Vec3& p : b.positions) p -= 2 * (p - onPlane).dot(normal) * normal;
    // The mirror turns its faces inside out: the second sphere is inward, as a segmentation's part may be.
    centreB = centreA - 2 * (centreA - onPlane).dot(normal) * normal;
    SurfaceMesh m = a;
    procedural::appendMesh(m, b);
    m.faces.push_back(m.faces[7]);
    m.faces.push_back(m.faces[a.faces.size() + 11]);
    m.faces.push_back({m.faces[3][0], m.faces[3][0], m.faces[3][1]});
    m.faces.push_back({m.faces[5][0], m.faces[5][1], m.faces[5][1]});
    completeMesh(m);
    return m;
}

TEST(SimulationReady, TouchingPartsOneInwardBecomeTwoClosedOutwardEvenPieces) {
    Vec3 centreA, centreB;
    double radius = 0;
    SurfaceMesh m = touchingSpheres(centreA, centreB, radius);
    ASSERT_GT((centreA - centreB).norm(), 1.9 * radius) << "the spheres touch, they do not overlap";
    const MeshReport before = validateMesh(m);
    ASSERT_FALSE(before.oriented);

    const RepairReport repair = cleanMesh(m, {.repair = true});
    EXPECT_EQ(repair.duplicateFaces, 2u);
    EXPECT_EQ(repair.degenerateFaces, 2u);
    EXPECT_GT(repair.separatedVertices, 0u);
    const MeshReport repaired = validateMesh(m);
    EXPECT_TRUE(repaired.closed && repaired.manifold && repaired.oriented);
    auto pieces = piecesOf(m);
    ASSERT_EQ(pieces.size(), 2u);
    for (const auto& piece : pieces) EXPECT_GT(signedVolumeOf(m, piece), 0) << "every closed piece outward";

    const std::size_t asked = 3000;
    const auto remeshed =
        remeshIsotropic(m, {.targetEdge_m = targetEdgeForTriangles(m, asked), .targetTriangles = asked});
    ASSERT_TRUE(remeshed) << remeshed.error();
    const SurfaceMesh& r = remeshed->mesh;
    const MeshReport after = validateMesh(r);
    EXPECT_TRUE(after.closed && after.manifold && after.oriented);
    EXPECT_GE(after.minAngleDeg, 25);
    EXPECT_NEAR(static_cast<double>(after.faces), static_cast<double>(asked), 0.05 * asked);
    pieces = piecesOf(r);
    ASSERT_EQ(pieces.size(), 2u);
    for (const auto& piece : pieces) EXPECT_GT(signedVolumeOf(r, piece), 0);
    // On the same surface: each vertex within 1% of the input's bounding-box diagonal of its sphere.
    const double diagonal = (before.bboxMax - before.bboxMin).norm();
    for (const Vec3& p : r.positions) {
        const double d = std::min(std::abs((p - centreA).norm() - radius), std::abs((p - centreB).norm() - radius));
        EXPECT_LT(d, 0.01 * diagonal);
    }
    EXPECT_LT(remeshed->distanceMax_m, 0.01 * diagonal);
}

// A whole organ written inside out (a tool that writes clockwise faces) comes back outward.
TEST(SimulationReady, AnInsideOutHeartIsTurnedOutward) {
    SurfaceMesh heart = procedural::makeHeart({.triangles = 4000});
    for (Face& f : heart.faces) std::swap(f[1], f[2]);
    completeMesh(heart);
    ASSERT_LT(test::signedVolume(heart), 0);
    ASSERT_TRUE(validateMesh(heart).oriented) << "consistent, only inward";
    const RepairReport r = cleanMesh(heart, {.repair = true});
    EXPECT_EQ(r.flippedFaces, heart.faces.size());
    EXPECT_GT(test::signedVolume(heart), 0);
    EXPECT_TRUE(validateMesh(heart).oriented);
}

}  // namespace
}  // namespace hapticut::mesh
