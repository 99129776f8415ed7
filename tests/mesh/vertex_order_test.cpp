// Vertex order for locality: a heart whose vertices were shuffled is renumbered in reverse Cuthill-McKee
// order into the same surface, with its UVs, parts and springs, and the same forces at the same places;
// separate parts are numbered one after another, each in a narrow band; a heart in its generator's order
// is left alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/vertex_order.h"
#include "hapticut/physics/material.h"
#include "hapticut/physics/spring_forces.h"
#include "test_support.h"

namespace hapticut::mesh {
namespace {

/// The heart with its vertices in random order and its faces in two named parts.
SurfaceMesh shuffledHeart(const SurfaceMesh& heart) {
    SurfaceMesh m = heart;
    std::vector<std::uint32_t> to(m.positions.size());
    std::iota(to.begin(), to.end(), 0u);
    std::shuffle(to.begin(), to.end(), std::mt19937(11));
    for (std::size_t i = 0; i < to.size(); ++i) m.positions[to[i]] = heart.positions[i];
    for (Face& f : m.faces)
        for (std::uint32_t& v : f) v = to[v];
    m.edges = edgesOfFaces(m.faces);
    m.partNames = {"front", "back"};
    m.faceParts.resize(m.faces.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) m.faceParts[f] = m.normals[f].z() > 0 ? 0 : 1;
    return m;
}

/// Each face as its corners' positions, UVs and part, starting at its lowest corner (so the orientation
/// counts but not where a face's list begins): equal for two meshes of the same surface however numbered.
std::vector<std::vector<double>> surfaceOf(const SurfaceMesh& m) {
    std::vector<std::vector<double>> faces;
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        int first = 0;
        for (int k = 1; k < 3; ++k)
            if (std::lexicographical_compare(m.positions[m.faces[f][k]].data(), m.positions[m.faces[f][k]].data() + 3,
                                             m.positions[m.faces[f][first]].data(),
                                             m.positions[m.faces[f][first]].data() + 3))
                first = k;
        std::vector<double> key;
        for (int k = 0; k < 3; ++k) {
            const int c = (first + k) % 3;
            const Vec3& p = m.positions[m.faces[f][c]];
            key.insert(key.end(), {p.x(), p.y(), p.z(), m.uvs[f][c].x(), m.uvs[f][c].y()});
        }
        key.push_back(m.partOf(f));
        faces.push_back(std::move(key));
    }
    std::sort(faces.begin(), faces.end());
    return faces;
}

TEST(VertexOrder, AShuffledHeartIsRenumberedIntoTheSameSurfaceWithItsNeighboursTogether) {
    const SurfaceMesh heart = procedural::makeHeart({.triangles = 9714});
    SurfaceMesh m = shuffledHeart(heart);
    const auto before = surfaceOf(m);
    const VertexOrderResult r = orderVerticesForLocality(m);
    ASSERT_TRUE(r.renumbered);
    EXPECT_LT(r.spanAfter, 0.25 * r.spanBefore);
    EXPECT_EQ(r.spanAfter, meanEdgeSpan(m));
    EXPECT_LT(r.spanAfter, 2 * meanEdgeSpan(heart)) << "about as local as the generator's own order";
    EXPECT_EQ(surfaceOf(m), before);
    EXPECT_EQ(m.edges, edgesOfFaces(m.faces));
    ASSERT_EQ(r.previousIndex.size(), m.positions.size());
    const SurfaceMesh shuffled = shuffledHeart(heart);
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        ASSERT_EQ(m.positions[i], shuffled.positions[r.previousIndex[i]]) << "vertex " << i;
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        ASSERT_TRUE(m.normals[f].isApprox((m.positions[m.faces[f][1]] - m.positions[m.faces[f][0]])
                                              .cross(m.positions[m.faces[f][2]] - m.positions[m.faces[f][0]])
                                              .normalized(),
                                          1e-9))
            << "face " << f << "'s normal did not go with it";
    const MeshReport report = validateMesh(m);
    EXPECT_TRUE(report.closed && report.manifold && report.oriented);
    EXPECT_EQ(report.components, 1u);
}

TEST(VertexOrder, AHeartInItsGeneratorsOrderIsLeftAsItIs) {
    const SurfaceMesh heart = procedural::makeHeart({.triangles = 9714});
    SurfaceMesh m = heart;
    const VertexOrderResult r = orderVerticesForLocality(m);
    EXPECT_FALSE(r.renumbered);
    EXPECT_EQ(r.spanBefore, r.spanAfter);
    EXPECT_EQ(m.positions, heart.positions);
    EXPECT_EQ(m.faces, heart.faces);
}

/// The largest difference in index between the ends of an edge: how wide a band of nodes a pass over
/// the springs works on.
std::uint32_t bandwidth(const SurfaceMesh& m) {
    std::uint32_t widest = 0;
    for (const Edge& e : m.edges) widest = std::max(widest, e[1] - e[0]);
    return widest;
}

TEST(VertexOrder, ShuffledPartsAreNumberedOneAfterAnotherEachInANarrowBand) {
    // Two hearts side by side, their vertices shuffled together, as an exporter might write an organ
    // of two parts.
    const SurfaceMesh heart = procedural::makeHeart({.triangles = 9714});
    SurfaceMesh two = heart;
    const auto n = static_cast<std::uint32_t>(heart.positions.size());
    for (const Vec3& p : heart.positions) two.positions.push_back(p + Vec3(0.2, 0, 0));
    for (Face f : heart.faces) {
        for (std::uint32_t& v : f) v += n;
        two.faces.push_back(f);
    }
    two.uvs.insert(two.uvs.end(), heart.uvs.begin(), heart.uvs.end());
    two.normals.insert(two.normals.end(), heart.normals.begin(), heart.normals.end());
    two.edges = edgesOfFaces(two.faces);
    SurfaceMesh m = shuffledHeart(two);
    ASSERT_TRUE(orderVerticesForLocality(m).renumbered);
    // Each part holds one range of indices.
    std::uint32_t lastLeft = 0, firstRight = 2 * n, lastRight = 0, firstLeft = 2 * n;
    for (std::uint32_t i = 0; i < 2 * n; ++i) {
        const bool left = m.positions[i].x() < 0.1;
        if (left)
            lastLeft = std::max(lastLeft, i), firstLeft = std::min(firstLeft, i);
        else
            lastRight = std::max(lastRight, i), firstRight = std::min(firstRight, i);
    }
    EXPECT_TRUE(lastLeft < firstRight || lastRight < firstLeft)
        << "left " << firstLeft << "-" << lastLeft << ", right " << firstRight << "-" << lastRight;
    // Every spring joins nodes of the same or neighbouring levels of the search, a band of about one
    // ring round the heart: under a twentieth of a part's nodes (131 of 4,860 here). A Morton curve's
    // jumps, and the generator's seam, span most of the part (4,053 and 3,917).
    EXPECT_LT(bandwidth(m), n / 20);
    EXPECT_LT(meanEdgeSpan(m), meanEdgeSpan(heart));
}

// The same tissue, only numbered otherwise: every node feels the same force at the same place.
TEST(VertexOrder, TheRenumberedModelPullsEveryPointAsTheShuffledOneDid) {
    SurfaceMesh shuffled = shuffledHeart(procedural::makeHeart({.triangles = 1619}));
    SurfaceMesh renumbered = shuffled;
    ASSERT_TRUE(orderVerticesForLocality(renumbered).renumbered);
    auto forces = [](const SurfaceMesh& m) {
        physics::MassSpringModel model = physics::buildModel(m, physics::Material{});
        std::map<std::array<double, 3>, Vec3> at;  // the force on the node at each rest position
        for (std::size_t i = 0; i < model.nodes.size(); ++i) {
            const Vec3 p = model.nodes.restPosition[i];
            model.nodes.position[i] =
                p + 1e-4 * Vec3(std::sin(4e2 * p.y()), std::cos(3e2 * p.z()), std::sin(5e2 * p.x()));
            model.nodes.velocity[i] = 1e-2 * Vec3(std::cos(3e2 * p.x()), 0.5, std::sin(2e2 * p.y()));
        }
        std::vector<Vec3> a(model.nodes.size());
        physics::computeAccelerations(model, model.nodes.position, model.nodes.velocity, a);
        for (std::size_t i = 0; i < model.nodes.size(); ++i) {
            const Vec3& p = model.nodes.restPosition[i];
            at[{p.x(), p.y(), p.z()}] = model.nodes.mass[i] * a[i];
        }
        return at;
    };
    const auto expected = forces(shuffled), actual = forces(renumbered);
    ASSERT_EQ(actual.size(), expected.size());
    double worst = 0, scale = 0;
    for (const auto& [p, f] : expected) {
        const auto it = actual.find(p);
        ASSERT_NE(it, actual.end());
        worst = std::max(worst, (it->second - f).norm()), scale = std::max(scale, f.norm());
    }
    EXPECT_GT(scale, 1e-3);
    EXPECT_LT(worst, 1e-12 * scale);
}

}  // namespace
}  // namespace hapticut::mesh
