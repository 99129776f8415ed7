// Vertex order for locality: reverse Cuthill-McKee over the mesh's edges.
#include "hapticut/mesh/vertex_order.h"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace hapticut::mesh {

namespace {

/// Each vertex's neighbours along the edges, as compressed rows (both directions of every edge).
struct Neighbours {
    std::vector<std::uint32_t> start, of;
    std::uint32_t degree(std::uint32_t v) const { return start[v + 1] - start[v]; }
};

Neighbours neighboursOf(std::size_t vertices, const std::vector<Edge>& edges) {
    Neighbours n;
    n.start.assign(vertices + 1, 0);
    for (const Edge& e : edges) ++n.start[e[0] + 1], ++n.start[e[1] + 1];
    for (std::size_t v = 0; v < vertices; ++v) n.start[v + 1] += n.start[v];
    n.of.resize(n.start.back());
    std::vector<std::uint32_t> next(n.start.begin(), n.start.end() - 1);
    for (const Edge& e : edges) n.of[next[e[0]]++] = e[1], n.of[next[e[1]]++] = e[0];
    return n;
}

struct Levels {
    std::uint32_t count = 0;
    std::size_t lastBegin = 0;  // where the last level starts in the order
};

/// Breadth-first from `root` over the unnumbered vertices, appending them to `order` level by level,
/// each vertex's unnumbered neighbours in increasing degree (Cuthill & McKee 1969). Marks them numbered.
Levels breadthFirst(const Neighbours& n, std::uint32_t root, std::vector<std::uint8_t>& numbered,
                    std::vector<std::uint32_t>& order) {
    order.push_back(root);
    numbered[root] = 1;
    Levels levels;
    for (std::size_t levelBegin = order.size() - 1; levelBegin < order.size(); ++levels.count) {
        levels.lastBegin = levelBegin;
        const std::size_t levelEnd = order.size();
        for (std::size_t k = levelBegin; k < levelEnd; ++k) {
            const std::size_t childrenBegin = order.size();
            for (std::uint32_t j = n.start[order[k]]; j < n.start[order[k] + 1]; ++j)
                if (!numbered[n.of[j]]) numbered[n.of[j]] = 1, order.push_back(n.of[j]);
            std::stable_sort(order.begin() + static_cast<std::ptrdiff_t>(childrenBegin), order.end(),
                             [&](std::uint32_t a, std::uint32_t b) { return n.degree(a) < n.degree(b); });
        }
        levelBegin = levelEnd;
    }
    return levels;
}

/// New index of each old vertex in reverse Cuthill-McKee order, one connected part after another. Each
/// part's search starts at a pseudo-peripheral vertex (George & Liu 1979): from any vertex, the last
/// level's vertex of least degree, again while that deepens the levels. Every edge then joins two
/// vertices of the same or neighbouring levels, so a pass over the springs works on a narrow band of
/// nodes at a time.
std::vector<std::uint32_t> cuthillMcKeeRanks(std::size_t vertices, const std::vector<Edge>& edges) {
    const Neighbours n = neighboursOf(vertices, edges);
    std::vector<std::uint8_t> numbered(vertices, 0);
    std::vector<std::uint32_t> order, trial;
    order.reserve(vertices);
    for (std::uint32_t seed = 0; seed < vertices; ++seed) {
        if (numbered[seed]) continue;
        std::uint32_t root = seed, depth = 0;
        for (int round = 0; round < 8; ++round) {  // two or three rounds settle it on a surface mesh
            trial.clear();
            const Levels levels = breadthFirst(n, root, numbered, trial);
            for (std::uint32_t v : trial) numbered[v] = 0;
            if (round > 0 && levels.count <= depth) break;
            depth = levels.count;
            root = *std::min_element(trial.begin() + static_cast<std::ptrdiff_t>(levels.lastBegin), trial.end(),
                                     [&](std::uint32_t a, std::uint32_t b) { return n.degree(a) < n.degree(b); });
        }
        breadthFirst(n, root, numbered, order);
    }
    std::vector<std::uint32_t> rank(vertices);
    for (std::size_t k = 0; k < order.size(); ++k) rank[order[k]] = static_cast<std::uint32_t>(vertices - 1 - k);
    return rank;
}

double meanSpanUnder(const SurfaceMesh& m, const std::vector<std::uint32_t>& rank) {
    if (m.edges.empty()) return 0;
    double sum = 0;
    for (const Edge& e : m.edges) {
        const std::uint32_t a = rank[e[0]], b = rank[e[1]];
        sum += a > b ? a - b : b - a;
    }
    return sum / static_cast<double>(m.edges.size());
}

}  // namespace

double meanEdgeSpan(const SurfaceMesh& mesh) {
    std::vector<std::uint32_t> identity(mesh.positions.size());
    std::iota(identity.begin(), identity.end(), 0u);
    return meanSpanUnder(mesh, identity);
}

VertexOrderResult orderVerticesForLocality(SurfaceMesh& m) {
    VertexOrderResult result;
    if (m.positions.size() < 2) return result;
    result.spanBefore = result.spanAfter = meanEdgeSpan(m);
    const std::vector<std::uint32_t> rank = cuthillMcKeeRanks(m.positions.size(), m.edges);
    const double span = meanSpanUnder(m, rank);
    // A careful generator's order (rings of a surface of revolution, slices of marching cubes) is as
    // good as any: only an order much worse than this one is replaced.
    if (!(span < 0.25 * result.spanBefore)) return result;
    std::vector<Vec3> positions(m.positions.size());
    for (std::size_t i = 0; i < rank.size(); ++i) positions[rank[i]] = m.positions[i];
    m.positions = std::move(positions);
    for (Face& f : m.faces)
        for (std::uint32_t& v : f) v = rank[v];
    for (Edge& e : m.edges) {
        e = {rank[e[0]], rank[e[1]]};
        if (e[0] > e[1]) std::swap(e[0], e[1]);
    }
    std::sort(m.edges.begin(), m.edges.end());
    // The faces too, so that a face's neighbours in the tree's leaves and the footprint sit nearby.
    std::vector<std::uint32_t> faceOrder(m.faces.size());
    std::iota(faceOrder.begin(), faceOrder.end(), 0u);
    auto lowest = [&](std::uint32_t f) { return *std::min_element(m.faces[f].begin(), m.faces[f].end()); };
    std::stable_sort(faceOrder.begin(), faceOrder.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return lowest(a) < lowest(b); });
    auto permute = [&](auto& values) {
        if (values.size() != faceOrder.size()) return;
        std::remove_reference_t<decltype(values)> sorted(values.size());
        for (std::size_t k = 0; k < faceOrder.size(); ++k) sorted[k] = values[faceOrder[k]];
        values = std::move(sorted);
    };
    permute(m.faces), permute(m.uvs), permute(m.normals), permute(m.faceParts);
    result.renumbered = true;
    result.spanAfter = span;
    result.previousIndex.resize(rank.size());
    for (std::uint32_t i = 0; i < rank.size(); ++i) result.previousIndex[rank[i]] = i;
    return result;
}

}  // namespace hapticut::mesh
