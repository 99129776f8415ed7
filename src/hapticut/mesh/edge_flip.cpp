// Edge flips that raise the smallest angle of a triangle pair.
#include "hapticut/mesh/edge_flip.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "hapticut/geometry/triangle.h"
#include "hapticut/mesh/adjacency.h"

namespace hapticut::mesh {

namespace {

/// Rotates f so that it starts at vertex v (f must contain v).
Face startingAt(const Face& f, std::uint32_t v) {
    if (f[1] == v) return {f[1], f[2], f[0]};
    if (f[2] == v) return {f[2], f[0], f[1]};
    return f;
}
}  // namespace

int improveByEdgeFlips(SurfaceMesh& mesh, const FlipOptions& options) {
    const auto& p = mesh.positions;
    // The smallest angle of a triangle is the one with the largest cosine: comparing cosines ranks
    // triangles the same way as angles without an atan2 per corner.
    auto maxCosine = [&](const Face& f) {
        double worst = -1;
        for (int k = 0; k < 3; ++k) {
            const Vec3 u = p[f[(k + 1) % 3]] - p[f[k]], v = p[f[(k + 2) % 3]] - p[f[k]];
            const double denom = std::sqrt(u.squaredNorm() * v.squaredNorm());
            worst = std::max(worst, denom > 0 ? u.dot(v) / denom : 1.0);
        }
        return worst;
    };
    const double goodEnough = std::cos(35.0 * 3.14159265358979 / 180);  // pairs with all angles above 35 deg stay
    int total = 0;
    for (int pass = 0; pass < options.maxPasses; ++pass) {
        const MeshAdjacency adj = buildAdjacency(mesh.faces);
        std::unordered_set<std::uint64_t> edges;
        edges.reserve(adj.edges.size() * 2);
        for (const Edge& e : adj.edges) edges.insert(edgeKey(e[0], e[1]));
        std::vector<char> touched(mesh.faces.size(), 0);  // a face flips at most once a pass: adjacency stays valid
        int flips = 0;
        for (std::size_t e = 0; e < adj.edges.size(); ++e) {
            const auto faces = adj.facesOfEdge(e);
            if (faces.size() != 2 || touched[faces[0]] || touched[faces[1]]) continue;
            // Name the pair (a, b, c) and (b, a, d), with a -> b the shared edge in the first face.
            Face f1 = startingAt(mesh.faces[faces[0]], adj.edges[e][0]);
            if (f1[1] != adj.edges[e][1]) f1 = startingAt(mesh.faces[faces[0]], adj.edges[e][1]);
            const std::uint32_t a = f1[0], b = f1[1], c = f1[2];
            const Face f2 = startingAt(mesh.faces[faces[1]], b);
            if (f2[1] != a) continue;  // inconsistent orientation: leave it alone
            const std::uint32_t d = f2[2];
            if (c == d || edges.count(edgeKey(c, d))) continue;  // the flip would duplicate an edge
            const double before = std::max(maxCosine(f1), maxCosine(f2));
            if (before < goodEnough) continue;

            const Vec3 n1 = geometry::unitNormal(p[a], p[b], p[c]), n2 = geometry::unitNormal(p[b], p[a], p[d]);
            if (n1.dot(n2) < options.minNormalCosine) continue;
            const Face g1{c, a, d}, g2{d, b, c};
            const Vec3 m1 = geometry::unitNormal(p[c], p[a], p[d]), m2 = geometry::unitNormal(p[d], p[b], p[c]);
            const Vec3 mean = n1 + n2;
            if (m1.dot(mean) <= 0 || m2.dot(mean) <= 0 || m1.dot(m2) < options.minNormalCosine) continue;  // would fold
            if (std::max(maxCosine(g1), maxCosine(g2)) >= before - 1e-9) continue;

            mesh.faces[faces[0]] = g1;
            mesh.faces[faces[1]] = g2;
            touched[faces[0]] = touched[faces[1]] = 1;
            edges.erase(edgeKey(a, b));
            edges.insert(edgeKey(c, d));
            ++flips;
        }
        total += flips;
        if (flips == 0) break;
    }
    mesh.edges = edgesOfFaces(mesh.faces);
    computeFaceNormals(mesh);
    return total;
}

}  // namespace hapticut::mesh
