// Choosing and summarising a model's named parts.
#include "hapticut/mesh/parts.h"

#include <algorithm>
#include <unordered_map>

namespace hapticut::mesh {

std::string listParts(const SurfaceMesh& m) {
    std::string out;
    for (std::size_t p = 0; p < m.partNames.size(); ++p)
        out += (p == 0 ? "'" : p + 1 == m.partNames.size() ? " and '" : ", '") + m.partNames[p] + "'";
    return out;
}

std::optional<std::string> selectParts(SurfaceMesh& m, std::span<const std::string> names) {
    if (names.empty()) return std::nullopt;
    if (!m.hasParts()) return "the model has no named parts (OBJ groups, or the meshes of a glTF, FBX or other file)";
    std::vector<char> wanted(m.partNames.size(), 0);
    for (const std::string& name : names) {
        const auto it = std::find(m.partNames.begin(), m.partNames.end(), name);
        if (it == m.partNames.end()) return "no part named '" + name + "': the model's parts are " + listParts(m);
        wanted[static_cast<std::size_t>(it - m.partNames.begin())] = 1;
    }
    keepFaces(m, [&](std::size_t f) { return wanted[m.faceParts[f]] != 0; });
    // The vertices the kept faces use, renumbered in their order.
    std::vector<std::uint32_t> index(m.positions.size(), ~std::uint32_t{0});
    std::vector<Vec3> positions;
    for (Face& face : m.faces)
        for (std::uint32_t& v : face) {
            if (index[v] == ~std::uint32_t{0}) {
                index[v] = static_cast<std::uint32_t>(positions.size());
                positions.push_back(m.positions[v]);
            }
            v = index[v];
        }
    m.positions = std::move(positions);
    // The parts kept, renumbered; one part left is a model of one part.
    std::vector<std::uint32_t> renumber(m.partNames.size(), 0);
    std::vector<std::string> kept;
    for (std::size_t p = 0; p < m.partNames.size(); ++p)
        if (wanted[p]) renumber[p] = static_cast<std::uint32_t>(kept.size()), kept.push_back(m.partNames[p]);
    for (std::uint32_t& p : m.faceParts) p = renumber[p];
    m.partNames = std::move(kept);
    if (m.partNames.size() < 2) m.partNames.clear(), m.faceParts.clear();
    m.edges = edgesOfFaces(m.faces);
    return std::nullopt;
}

std::vector<PartSummary> summariseParts(const SurfaceMesh& m) {
    std::vector<PartSummary> parts(m.hasParts() ? m.partNames.size() : 0);
    if (parts.empty()) return parts;
    std::vector<std::unordered_map<std::uint64_t, int>> edgeUses(parts.size());
    std::vector<std::vector<std::uint32_t>> vertices(parts.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        const std::uint32_t p = m.faceParts[f];
        ++parts[p].faces;
        for (int k = 0; k < 3; ++k) {
            ++edgeUses[p][edgeKey(m.faces[f][k], m.faces[f][(k + 1) % 3])];
            vertices[p].push_back(m.faces[f][k]);
        }
    }
    for (std::size_t p = 0; p < parts.size(); ++p) {
        parts[p].name = m.partNames[p];
        for (const auto& [edge, uses] : edgeUses[p]) parts[p].boundaryEdges += uses == 1;
        std::sort(vertices[p].begin(), vertices[p].end());
        parts[p].vertices =
            static_cast<std::size_t>(std::unique(vertices[p].begin(), vertices[p].end()) - vertices[p].begin());
    }
    return parts;
}

}  // namespace hapticut::mesh
