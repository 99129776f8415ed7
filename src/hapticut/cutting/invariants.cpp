// The guarantees cutting keeps.
#include "hapticut/cutting/invariants.h"

#include <algorithm>
#include <cmath>

#include "hapticut/geometry/triangle.h"
#include "hapticut/mesh/adjacency.h"

namespace hapticut::cutting {

InvariantReport checkInvariants(const CutModel& cut, const double expected_mass_kg, const bool closed) {
    InvariantReport r;
    auto problem = [&](std::string s) {
        if (r.problems.size() < 20) r.problems.push_back(std::move(s));
    };
    const mesh::SurfaceMesh& m = cut.mesh();
    const physics::MassSpringModel& model = cut.model();
    const physics::Springs& s = model.springs;
    if (model.nodes.size() != m.positions.size())
        problem("the model has " + std::to_string(model.nodes.size()) + " nodes for " +
                std::to_string(m.positions.size()) + " vertices");
    if (m.uvs.size() != m.faces.size()) problem("UVs and faces differ in count");
    if (m.hasParts() && m.faceParts.size() != m.faces.size()) problem("parts and faces differ in count");

    const mesh::MeshAdjacency adj = mesh::buildAdjacency(m.faces);
    for (std::size_t e = 0; e < adj.edges.size(); ++e) {
        const auto faces = adj.facesOfEdge(e);
        // Named, not a structured binding: the lambda below captures them, which clang before 16 refuses.
        const std::uint32_t a = adj.edges[e][0], b = adj.edges[e][1];
        if (closed && faces.size() == 1)
            problem("edge (" + std::to_string(a) + ", " + std::to_string(b) +
                    ") is open, but the organ was closed: a wound without its walls");
        if (faces.size() > 2)
            problem("edge (" + std::to_string(a) + ", " + std::to_string(b) + ") has " + std::to_string(faces.size()) +
                    " faces");
        if (faces.size() == 2) {
            auto forward = [&](std::uint32_t f) {
                for (int k = 0; k < 3; ++k)
                    if (m.faces[f][k] == a && m.faces[f][(k + 1) % 3] == b) return true;
                return false;
            };
            if (forward(faces[0]) == forward(faces[1]))
                problem("faces " + std::to_string(faces[0]) + " and " + std::to_string(faces[1]) +
                        " disagree in orientation");
        }
        const auto spring = cut.springOf(a, b);
        if (!spring) problem("edge (" + std::to_string(a) + ", " + std::to_string(b) + ") has no spring");
    }
    // Vertex-manifold: the faces round each vertex form one fan, joined across the edges through it
    // that two faces share; two fans touching only at a vertex are a pinch. Corner 3f + k is vertex
    // faces[f][k] in face f; each shared edge joins its two faces' corners at both of its ends.
    std::vector<std::uint32_t> parent(3 * m.faces.size());
    for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
    auto root = [&](std::uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    auto cornerOf = [&](std::uint32_t f, std::uint32_t v) {
        int k = 0;
        while (k < 2 && m.faces[f][k] != v) ++k;
        return 3 * f + static_cast<std::uint32_t>(k);
    };
    for (std::size_t e = 0; e < adj.edges.size(); ++e) {
        const auto faces = adj.facesOfEdge(e);
        if (faces.size() != 2) continue;
        for (std::uint32_t v : adj.edges[e]) parent[root(cornerOf(faces[0], v))] = root(cornerOf(faces[1], v));
    }
    std::vector<std::uint32_t> fans(m.positions.size(), 0);
    for (std::uint32_t c = 0; c < parent.size(); ++c)
        if (root(c) == c && m.faces[c / 3][c % 3] < fans.size()) ++fans[m.faces[c / 3][c % 3]];
    for (std::uint32_t v = 0; v < fans.size(); ++v)
        if (fans[v] > 1)
            problem("vertex " + std::to_string(v) + " joins " + std::to_string(fans[v]) +
                    " fans of faces that touch only there");

    // Each vertex's edges to higher vertices are a run of the sorted edges: a spring's edge is looked for
    // in its lower end's run, and counted there, so an edge with two springs shows without a sort.
    std::size_t vertices = m.positions.size();
    for (const mesh::Edge& e : adj.edges) vertices = std::max<std::size_t>(vertices, std::size_t{e[1]} + 1);
    std::vector<std::size_t> edgesFrom(vertices + 1, 0);
    for (const mesh::Edge& e : adj.edges) ++edgesFrom[e[0] + 1];
    for (std::size_t v = 0; v < vertices; ++v) edgesFrom[v + 1] += edgesFrom[v];
    std::vector<std::uint8_t> springsOnEdge(adj.edges.size(), 0);
    bool twoOnAnEdge = false;
    for (std::size_t k = 0; k < s.size(); ++k) {
        const mesh::Edge e{std::min(s.a[k], s.b[k]), std::max(s.a[k], s.b[k])};
        std::size_t edge = e[0] < vertices ? edgesFrom[e[0]] : 0, end = e[0] < vertices ? edgesFrom[e[0] + 1] : 0;
        while (edge < end && adj.edges[edge][1] != e[1]) ++edge;
        if (edge == end)
            problem("spring " + std::to_string(k) + " is on no face");
        else
            twoOnAnEdge |= ++springsOnEdge[edge] > 1;
        if (cut.springOf(e[0], e[1]) != k) problem("spring " + std::to_string(k) + " is not the one its edge looks up");
        if (!(s.restLength[k] > 0) || !std::isfinite(s.stiffness[k]))
            problem("spring " + std::to_string(k) + " has a bad rest length or stiffness");
        if (k < m.edges.size() &&
            (std::min(m.edges[k][0], m.edges[k][1]) != e[0] || std::max(m.edges[k][0], m.edges[k][1]) != e[1]))
            problem("edge list entry " + std::to_string(k) + " is not spring " + std::to_string(k));
    }
    if (twoOnAnEdge) problem("an edge has two springs");

    // geometry::minAngle(...) <= 0 without its arc tangents where it cannot be: an angle is positive
    // wherever its corner's cross product is not zero.
    auto degenerate = [](const Vec3& a, const Vec3& b, const Vec3& c) {
        const Vec3 ab = b - a, bc = c - b, ca = a - c;
        if (ab.cross(ca).squaredNorm() > 0 && bc.cross(ab).squaredNorm() > 0 && ca.cross(bc).squaredNorm() > 0)
            return false;
        return geometry::minAngle(a, b, c) <= 0;
    };
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) {
        const mesh::Face& face = m.faces[f];
        if (degenerate(m.positions[face[0]], m.positions[face[1]], m.positions[face[2]]))
            problem("face " + std::to_string(f) + " is degenerate");
        for (std::uint32_t v : face) {
            const auto& around = cut.facesAround(v);
            if (std::find(around.begin(), around.end(), f) == around.end())
                problem("vertex " + std::to_string(v) + " does not list face " + std::to_string(f));
        }
        for (const Vec2& uv : m.uvs[f])
            if (!uv.allFinite()) problem("face " + std::to_string(f) + " has a non-finite UV");
    }
    double mass = 0;
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
        mass += model.nodes.mass[i];
        if (!model.nodes.position[i].allFinite() || !model.nodes.velocity[i].allFinite() || !m.positions[i].allFinite())
            problem("node " + std::to_string(i) + " is not finite");
    }
    if (std::abs(mass - expected_mass_kg) > 1e-12 * std::max(1.0, expected_mass_kg))
        problem("total mass " + std::to_string(mass) + " kg, expected " + std::to_string(expected_mass_kg));
    return r;
}

}  // namespace hapticut::cutting
