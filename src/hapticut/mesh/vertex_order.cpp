// Morton order of a mesh's vertices.
#include "hapticut/mesh/vertex_order.h"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace hapticut::mesh {

namespace {

/// The 21 low bits of v spread to every third bit.
std::uint64_t spreadBits(std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

/// new index of each old vertex, along the Morton curve through the bounding box.
std::vector<std::uint32_t> mortonRanks(const std::vector<Vec3>& positions) {
    Vec3 lo = positions.front(), hi = lo;
    for (const Vec3& p : positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
    const double scale = static_cast<double>((1u << 21) - 1) / extent;  // one cube, so the curve is not squashed
    std::vector<std::uint64_t> code(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const Vec3 q = (positions[i] - lo) * scale;
        code[i] = spreadBits(static_cast<std::uint64_t>(q.x())) | spreadBits(static_cast<std::uint64_t>(q.y())) << 1 |
                  spreadBits(static_cast<std::uint64_t>(q.z())) << 2;
    }
    std::vector<std::uint32_t> byCode(positions.size());
    std::iota(byCode.begin(), byCode.end(), 0u);
    std::stable_sort(byCode.begin(), byCode.end(), [&](std::uint32_t a, std::uint32_t b) { return code[a] < code[b]; });
    std::vector<std::uint32_t> rank(positions.size());
    for (std::uint32_t k = 0; k < byCode.size(); ++k) rank[byCode[k]] = k;
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
    const std::vector<std::uint32_t> rank = mortonRanks(m.positions);
    const double span = meanSpanUnder(m, rank);
    // A Morton curve has jumps of its own, larger than a careful generator's order: only an order much
    // worse than it is replaced.
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
