// Edge and face adjacency against a plain map of each edge's faces, on random soups of faces that have
// what imported meshes have: edges of one, two and three faces, faces with a repeated corner, unused
// vertex numbers, and numbers far beyond the faces' count.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "hapticut/mesh/adjacency.h"

namespace hapticut::mesh {
namespace {

void expectAdjacencyOf(const std::vector<Face>& faces) {
    std::map<Edge, std::vector<std::uint32_t>> facesOf;  // faces in order, a face once per corner on the edge
    for (std::uint32_t f = 0; f < faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = faces[f][k], b = faces[f][(k + 1) % 3];
            facesOf[{std::min(a, b), std::max(a, b)}].push_back(f);
        }
    const MeshAdjacency adj = buildAdjacency(faces);
    ASSERT_EQ(adj.edges.size(), facesOf.size());
    std::size_t e = 0;
    for (const auto& [edge, expected] : facesOf) {
        EXPECT_EQ(adj.edges[e], edge);
        const auto got = adj.facesOfEdge(e);
        EXPECT_EQ(std::vector<std::uint32_t>(got.begin(), got.end()), expected) << "edge " << edge[0] << "-" << edge[1];
        ++e;
    }
    for (std::uint32_t f = 0; f < faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = faces[f][k], b = faces[f][(k + 1) % 3];
            const Edge edge{std::min(a, b), std::max(a, b)};
            ASSERT_EQ(adj.edges[adj.faceEdges[f][k]], edge);
            const std::vector<std::uint32_t>& of = facesOf[edge];
            const std::uint32_t across = of.size() == 2 ? (of[0] == f ? of[1] : of[0]) : kNoFace;
            EXPECT_EQ(adj.faceNeighbours[f][k], across) << "face " << f << " corner " << k;
        }
}

TEST(Adjacency, EveryEdgeListsItsFacesInOrderAndEveryFaceItsNeighbours) {
    std::mt19937 random(7);
    for (const std::uint32_t vertices : {4u, 30u, 1000u}) {
        std::uniform_int_distribution<std::uint32_t> vertex(0, vertices - 1);
        std::vector<Face> faces;
        for (int f = 0; f < 3000; ++f) faces.push_back({vertex(random), vertex(random), vertex(random)});
        expectAdjacencyOf(faces);
    }
}

TEST(Adjacency, VertexNumbersFarBeyondTheFacesCountGiveTheSameOrder) {
    std::vector<Face> faces = {{0, 1, 2}, {2, 1, 4'000'000'000u}, {4'000'000'000u, 1, 7}, {2, 0, 3'000'000'000u}};
    expectAdjacencyOf(faces);
}

}  // namespace
}  // namespace hapticut::mesh
