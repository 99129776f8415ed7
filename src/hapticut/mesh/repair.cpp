// Cleaning and repairing imported meshes.
#include "hapticut/mesh/repair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <unordered_map>

#include "hapticut/geometry/aabb.h"
#include "hapticut/geometry/triangle.h"
#include "hapticut/mesh/adjacency.h"
#include "hapticut/mesh/uv_projection.h"
#include "hapticut/mesh/vertex_faces.h"

namespace hapticut::mesh {

namespace {

std::string count(std::size_t n, const char* what) { return std::to_string(n) + " " + what; }

/// Joins vertices within eps: a grid of cells eps wide, each vertex compared with the representatives
/// in its own and the 26 neighbouring cells.
std::size_t weld(SurfaceMesh& m, double eps) {
    std::vector<std::uint32_t> remap(m.positions.size());
    std::vector<Vec3> kept;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;
    const double cell = std::max(eps, 1e-300);
    // A tolerance of zero (every vertex at one point) or coordinates far larger than the cell give cell
    // numbers past the range of an integer; clamped, far vertices share an edge cell and are still told
    // apart by their distance.
    constexpr double kLastCell = 0x1p52;
    auto cellOf = [cell](double c) {
        const double n = std::floor(c / cell);
        return static_cast<long long>(n >= -kLastCell && n <= kLastCell ? n : std::copysign(kLastCell, n));
    };
    auto key = [](long long x, long long y, long long z) {
        return (static_cast<std::uint64_t>(x) * 73856093u) ^ (static_cast<std::uint64_t>(y) * 19349663u) ^
               (static_cast<std::uint64_t>(z) * 83492791u);
    };
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const Vec3& p = m.positions[i];
        const long long cx = cellOf(p.x()), cy = cellOf(p.y()), cz = cellOf(p.z());
        std::int64_t found = -1;
        for (long long dx = -1; dx <= 1 && found < 0; ++dx)
            for (long long dy = -1; dy <= 1 && found < 0; ++dy)
                for (long long dz = -1; dz <= 1 && found < 0; ++dz) {
                    const auto it = cells.find(key(cx + dx, cy + dy, cz + dz));
                    if (it == cells.end()) continue;
                    for (std::uint32_t r : it->second)
                        if ((kept[r] - p).norm() <= eps) {
                            found = r;
                            break;
                        }
                }
        if (found < 0) {
            found = static_cast<std::int64_t>(kept.size());
            kept.push_back(p);
            cells[key(cx, cy, cz)].push_back(static_cast<std::uint32_t>(found));
        }
        remap[i] = static_cast<std::uint32_t>(found);
    }
    const std::size_t welded = m.positions.size() - kept.size();
    m.positions = std::move(kept);
    for (Face& f : m.faces)
        for (std::uint32_t& v : f) v = remap[v];
    return welded;
}

std::size_t dropUnusedVertices(SurfaceMesh& m) {
    std::vector<std::uint32_t> remap(m.positions.size(), kNoFace);
    std::vector<Vec3> kept;
    for (Face& f : m.faces)
        for (std::uint32_t& v : f) {
            if (remap[v] == kNoFace) {
                remap[v] = static_cast<std::uint32_t>(kept.size());
                kept.push_back(m.positions[v]);
            }
            v = remap[v];
        }
    const std::size_t removed = m.positions.size() - kept.size();
    m.positions = std::move(kept);
    return removed;
}

void flip(SurfaceMesh& m, std::size_t f) {
    std::swap(m.faces[f][1], m.faces[f][2]);
    std::swap(m.uvs[f][1], m.uvs[f][2]);
}

/// Pieces that touch at non-manifold edges or vertices (an atlas's chambers, valves and vessels, each
/// closed on its own) are parted: a piece is the faces joined across edges that exactly two faces
/// share, and at each vertex every piece but the first gets its own copy. Splitting an edge's faces
/// beyond the first two instead would pair faces of different pieces, open both, and orient one by
/// the other (inward). Returns the vertices copied.
std::size_t separateTouchingPieces(SurfaceMesh& m) {
    const std::vector<std::uint32_t> pieceOf = facePieces(buildAdjacency(m.faces), true);
    const VertexFaces around = buildVertexFaces(m.faces, m.positions.size());
    const std::size_t vertexCount = m.positions.size();
    std::size_t copies = 0;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pieceCopy;  // (piece, its vertex) at this vertex
    for (std::uint32_t v = 0; v < vertexCount; ++v) {
        pieceCopy.clear();
        for (const std::uint32_t f : around.of(v)) {
            const std::uint32_t piece = pieceOf[f];
            auto it = std::find_if(pieceCopy.begin(), pieceCopy.end(), [&](const auto& p) { return p.first == piece; });
            if (it == pieceCopy.end()) {
                std::uint32_t copy = v;
                if (!pieceCopy.empty()) {
                    copy = static_cast<std::uint32_t>(m.positions.size());
                    m.positions.push_back(m.positions[v]);
                    ++copies;
                }
                pieceCopy.emplace_back(piece, copy);
                it = pieceCopy.end() - 1;
            }
            for (std::uint32_t& corner : m.faces[f])
                if (corner == v) corner = it->second;
        }
    }
    return copies;
}

/// Faces beyond the first two on an edge get their own copies of the edge's two vertices: what is left
/// after separateTouchingPieces, three or more faces of one piece on an edge (a fin).
std::size_t splitNonManifoldEdges(SurfaceMesh& m) {
    const MeshAdjacency adj = buildAdjacency(m.faces);
    std::size_t split = 0;
    for (std::size_t e = 0; e < adj.edges.size(); ++e) {
        const auto faces = adj.facesOfEdge(e);
        if (faces.size() <= 2) continue;
        ++split;
        for (std::size_t i = 2; i < faces.size(); ++i)
            for (std::uint32_t v : adj.edges[e]) {
                const auto copy = static_cast<std::uint32_t>(m.positions.size());
                m.positions.push_back(m.positions[v]);
                for (std::uint32_t& corner : m.faces[faces[i]])
                    if (corner == v) corner = copy;
            }
    }
    return split;
}

/// A vertex where separate fans of faces meet (a bowtie) gets one copy per extra fan. Fans are the
/// groups of the vertex's faces connected through edges that contain the vertex.
std::size_t splitNonManifoldVertices(SurfaceMesh& m) {
    const MeshAdjacency adj = buildAdjacency(m.faces);
    const VertexFaces around = buildVertexFaces(m.faces, m.positions.size());
    std::size_t split = 0;
    std::vector<std::uint32_t> fan;
    const std::size_t vertexCount = m.positions.size();
    for (std::uint32_t v = 0; v < vertexCount; ++v) {
        const auto faces = around.of(v);
        if (faces.size() < 2) continue;
        fan.assign(faces.size(), kNoFace);
        std::uint32_t fans = 0;
        for (std::size_t seed = 0; seed < faces.size(); ++seed) {
            if (fan[seed] != kNoFace) continue;
            std::vector<std::size_t> todo{seed};
            fan[seed] = fans;
            while (!todo.empty()) {
                const std::uint32_t f = faces[todo.back()];
                todo.pop_back();
                for (int k = 0; k < 3; ++k) {
                    const Edge& e = adj.edges[adj.faceEdges[f][k]];
                    if (e[0] != v && e[1] != v) continue;  // only edges through the vertex join fans
                    for (std::uint32_t g : adj.facesOfEdge(adj.faceEdges[f][k]))
                        for (std::size_t j = 0; j < faces.size(); ++j)
                            if (faces[j] == g && fan[j] == kNoFace) fan[j] = fans, todo.push_back(j);
                }
            }
            ++fans;
        }
        if (fans < 2) continue;
        ++split;
        for (std::uint32_t extra = 1; extra < fans; ++extra) {
            const auto copy = static_cast<std::uint32_t>(m.positions.size());
            m.positions.push_back(m.positions[v]);
            for (std::size_t j = 0; j < faces.size(); ++j)
                if (fan[j] == extra)
                    for (std::uint32_t& corner : m.faces[faces[j]])
                        if (corner == v) corner = copy;
        }
    }
    return split;
}

/// The piece of `seed` (the faces joined across edges that exactly two faces share), breadth first into
/// `members`, each marked `mark` in `piece`. meet(f, k, g, first) is called for face f's edge k and the
/// face g across it, with `first` when g is met for the first time (before it is marked, so that the
/// caller may flip it). Returns whether the piece is closed: no edge of it has one face or more than two.
template <class Meet>
bool gatherPiece(const MeshAdjacency& adj, std::uint32_t seed, std::uint32_t mark, std::vector<std::uint32_t>& piece,
                 std::vector<std::uint32_t>& members, Meet&& meet) {
    members.assign(1, seed);
    piece[seed] = mark;
    bool closed = true;
    for (std::size_t next = 0; next < members.size(); ++next) {
        const std::uint32_t f = members[next];
        for (int k = 0; k < 3; ++k) {
            const auto faces = adj.facesOfEdge(adj.faceEdges[f][k]);
            if (faces.size() != 2) {
                closed = false;
                continue;
            }
            const std::uint32_t g = faces[0] == f ? faces[1] : faces[0];
            const bool first = piece[g] == kNoFace;
            meet(f, k, g, first);
            if (!first) continue;
            piece[g] = mark;
            members.push_back(g);
        }
    }
    return closed;
}

/// Six times the volume a closed piece encloses, positive when its faces face out. About a corner of
/// the piece rather than the origin: a segmentation in body coordinates sits far from it, and the
/// terms would cancel.
double enclosedVolume6(const SurfaceMesh& m, std::span<const std::uint32_t> members) {
    const Vec3 origin = m.positions[m.faces[members.front()][0]];
    double volume = 0;
    for (std::uint32_t f : members) {
        const Face& c = m.faces[f];
        volume += (m.positions[c[0]] - origin).dot((m.positions[c[1]] - origin).cross(m.positions[c[2]] - origin));
    }
    return volume;
}

/// Flips faces so that neighbours agree (breadth-first over manifold edges), then turns each closed
/// piece outward (positive enclosed volume). Returns the faces flipped and the piece of each face.
std::size_t orient(SurfaceMesh& m, std::vector<std::uint32_t>& component) {
    const MeshAdjacency adj = buildAdjacency(m.faces);
    component.assign(m.faces.size(), kNoFace);
    std::size_t flipped = 0;
    std::uint32_t pieces = 0;
    std::vector<std::uint32_t> members;
    for (std::uint32_t seed = 0; seed < m.faces.size(); ++seed) {
        if (component[seed] != kNoFace) continue;
        const bool closed = gatherPiece(
            adj, seed, pieces, component, members, [&](std::uint32_t f, int k, std::uint32_t g, bool first) {
                // a neighbour must run the shared edge b -> a
                if (first && traversesForward(m.faces[g], m.faces[f][k], m.faces[f][(k + 1) % 3]))
                    flip(m, g), ++flipped;
            });
        if (closed && enclosedVolume6(m, members) < 0)
            for (std::uint32_t f : members) flip(m, f), ++flipped;
        ++pieces;
    }
    return flipped;
}

}  // namespace

TurnedOutward turnInsideOutPiecesOutward(SurfaceMesh& m) {
    TurnedOutward turned;
    const MeshAdjacency adj = buildAdjacency(m.faces);
    std::vector<std::uint32_t> piece(m.faces.size(), kNoFace), members;
    std::vector<char> partNamed(m.partNames.size(), 0);
    for (std::uint32_t seed = 0; seed < m.faces.size(); ++seed) {
        if (piece[seed] != kNoFace) continue;
        bool consistent = true;  // neighbours that agree run their shared edge in opposite directions
        const bool closed =
            gatherPiece(adj, seed, seed, piece, members, [&](std::uint32_t f, int k, std::uint32_t g, bool) {
                if (traversesForward(m.faces[g], m.faces[f][k], m.faces[f][(k + 1) % 3])) consistent = false;
            });
        if (!closed || !consistent || !(enclosedVolume6(m, members) < 0)) continue;
        for (std::uint32_t f : members) {
            std::swap(m.faces[f][1], m.faces[f][2]);
            if (m.uvs.size() == m.faces.size()) std::swap(m.uvs[f][1], m.uvs[f][2]);  // a file may come without
            const std::uint32_t part = m.partOf(f);
            if (part < partNamed.size() && !partNamed[part])
                partNamed[part] = 1, turned.parts.push_back(m.partNames[part]);
        }
        ++turned.pieces;
        turned.faces += members.size();
    }
    if (turned.faces > 0) computeFaceNormals(m);
    return turned;
}

RepairReport cleanMesh(SurfaceMesh& m, const RepairOptions& options) {
    RepairReport r;
    if (m.uvs.size() != m.faces.size()) m.uvs.assign(m.faces.size(), FaceUvs{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()});
    const geometry::Aabb box = geometry::boundsOf(m.positions);
    // stableNorm: the diagonal of a model with coordinates of 1e200 must not overflow into a tolerance
    // that welds every vertex into one.
    const double eps = options.weldEpsilon_m >= 0 ? options.weldEpsilon_m : 1e-9 * box.extent().stableNorm();
    if ((r.weldedVertices = weld(m, eps)) > 0)
        r.notes.push_back("welded " + count(r.weldedVertices, "duplicate vertices"));

    r.degenerateFaces = keepFaces(m, [&](std::size_t i) {
        const Face& f = m.faces[i];
        return f[0] != f[1] && f[1] != f[2] && f[0] != f[2] &&
               geometry::areaNormal(m.positions[f[0]], m.positions[f[1]], m.positions[f[2]]).squaredNorm() > 0;
    });
    if (r.degenerateFaces > 0) r.notes.push_back("dropped " + count(r.degenerateFaces, "degenerate faces"));
    std::vector<std::array<std::uint32_t, 4>> sorted;  // sorted corners + face index
    for (std::uint32_t i = 0; i < m.faces.size(); ++i) {
        Face f = m.faces[i];
        std::sort(f.begin(), f.end());
        sorted.push_back({f[0], f[1], f[2], i});
    }
    std::sort(sorted.begin(), sorted.end());
    std::vector<char> duplicate(m.faces.size(), 0);
    for (std::size_t i = 1; i < sorted.size(); ++i)
        if (sorted[i][0] == sorted[i - 1][0] && sorted[i][1] == sorted[i - 1][1] && sorted[i][2] == sorted[i - 1][2])
            duplicate[sorted[i][3]] = 1;
    r.duplicateFaces = keepFaces(m, [&](std::size_t i) { return !duplicate[i]; });
    if (r.duplicateFaces > 0) r.notes.push_back("dropped " + count(r.duplicateFaces, "duplicate faces"));

    if (options.repair) {
        if ((r.separatedVertices = separateTouchingPieces(m)) > 0)
            r.notes.push_back("parted pieces that touched at non-manifold edges or vertices (" +
                              count(r.separatedVertices, "vertices copied") + ")");
        if ((r.splitNonManifoldEdges = splitNonManifoldEdges(m)) > 0)
            r.notes.push_back("split " + count(r.splitNonManifoldEdges, "non-manifold edges"));
        if ((r.splitNonManifoldVertices = splitNonManifoldVertices(m)) > 0)
            r.notes.push_back("split " + count(r.splitNonManifoldVertices, "non-manifold vertices"));
        std::vector<std::uint32_t> component;
        if ((r.flippedFaces = orient(m, component)) > 0)
            r.notes.push_back("flipped " + count(r.flippedFaces, "faces to a consistent, outward orientation"));
        const std::uint32_t pieces = m.faces.empty() ? 0 : *std::max_element(component.begin(), component.end()) + 1;
        std::vector<std::size_t> size(pieces, 0);
        for (std::uint32_t c : component) ++size[c];
        const std::size_t largest = size.empty() ? 0 : *std::max_element(size.begin(), size.end());
        std::vector<char> drop(pieces, 0);
        for (std::uint32_t c = 0; c < pieces; ++c)
            if (static_cast<double>(size[c]) < options.minComponentShare * static_cast<double>(m.faces.size()) &&
                size[c] < largest) {
                drop[c] = 1;
                ++r.removedComponents;
                r.removedComponentFaces += size[c];
            }
        keepFaces(m, [&](std::size_t i) { return !drop[component[i]]; });
        if (r.removedComponents > 0)
            r.notes.push_back("removed " + count(r.removedComponents, "small fragments") + " (" +
                              count(r.removedComponentFaces, "faces") + ")");
    }
    if ((r.unusedVertices = dropUnusedVertices(m)) > 0)
        r.notes.push_back("dropped " + count(r.unusedVertices, "unused vertices"));

    const bool hasUvs = std::any_of(m.uvs.begin(), m.uvs.end(), [](const FaceUvs& uv) {
        return !uv[0].isZero() || !uv[1].isZero() || !uv[2].isZero();
    });
    if (!hasUvs && !m.faces.empty()) {
        sphericalUvs(m, geometry::boundsOf(m.positions).center());
        r.generatedUvs = true;
        r.notes.push_back("generated spherical texture coordinates");
    }
    computeFaceNormals(m);
    m.edges = edgesOfFaces(m.faces);
    return r;
}

void fitUnitBox(SurfaceMesh& m) {
    const geometry::Aabb box = geometry::boundsOf(m.positions);
    const double size = box.extent().maxCoeff();
    if (!(size > 0)) return;
    const Vec3 centre = box.center();
    for (Vec3& p : m.positions) p = (p - centre) / size;
    m.edges = m.edges.empty() ? edgesOfFaces(m.faces) : m.edges;
}

}  // namespace hapticut::mesh
