// Isotropic remeshing (Botsch & Kobbelt 2004) on an indexed face set with per-vertex face lists.
#include "hapticut/mesh/remesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <span>
#include <unordered_map>
#include <unordered_set>

#include "hapticut/geometry/aabb.h"
#include "hapticut/geometry/triangle.h"
#include "hapticut/geometry/triangle_queries.h"
#include "hapticut/mesh/adjacency.h"
#include "hapticut/mesh/edge_flip.h"

namespace hapticut::mesh {

namespace {

/// The sine of a triangle's smallest angle (0 for a degenerate one): twice the area over the product of
/// the two edges beside that angle, which are the two longest.
double smallestAngleSine(const Vec3& a, const Vec3& b, const Vec3& c) {
    std::array<double, 3> l{(b - a).norm(), (c - b).norm(), (a - c).norm()};
    std::sort(l.begin(), l.end());
    const double twiceArea = (b - a).cross(c - a).norm();
    return l[1] * l[2] > 0 ? twiceArea / (l[1] * l[2]) : 0;
}

/// An input with more than this share of its edges folded (its two faces facing apart) is rough, as a
/// jittered segmentation is (10-15%; a clean one, marching tetrahedra's slivers and all, has none), and
/// is smoothed before the passes (Remesher::lowPass) in kRoughInputRounds rounds.
constexpr double kRoughInput = 0.01;
constexpr int kRoughInputRounds = 2;
/// Collapses do not make triangles thinner than this (sin 15 degrees) where they were not already.
constexpr double kSliverSine = 0.2588;
/// Triangles with an angle under 30 degrees (its sine), or folded, are mended after the passes.
constexpr double kMendSine = 0.5;

/// The input's triangles in a uniform grid, for the closest point on the input surface. Each cell's
/// triangles are a run of one array (compressed rows), so a grid of millions of cells, most of them
/// empty, costs four bytes a cell.
class SurfaceGrid {
public:
    /// Cells of about `cell` metres, larger where more than kMaxCells of them would fill the box.
    SurfaceGrid(const SurfaceMesh& m, double cell) : m_(m) {
        for (const Vec3& p : m.positions) box_.grow(p);
        const Vec3 extent = box_.extent();
        const double cells = ((extent / cell).array().floor() + 1).prod();
        cell_ = cells > kMaxCells ? cell * std::cbrt(cells / kMaxCells) * 1.01 : cell;
        dims_ = ((extent / cell_).array().floor().cast<int>() + 1).max(1);
        start_.assign(static_cast<std::size_t>(dims_.x()) * dims_.y() * dims_.z() + 1, 0);
        auto forCellsOf = [&](std::uint32_t f, auto&& visit) {
            geometry::Aabb b;
            for (std::uint32_t v : m.faces[f]) b.grow(m.positions[v]);
            const Eigen::Array3i lo = cellOf(b.min), hi = cellOf(b.max);
            for (int x = lo.x(); x <= hi.x(); ++x)
                for (int y = lo.y(); y <= hi.y(); ++y)
                    for (int z = lo.z(); z <= hi.z(); ++z) visit(index(x, y, z));
        };
        for (std::uint32_t f = 0; f < m.faces.size(); ++f) forCellsOf(f, [&](std::size_t c) { ++start_[c + 1]; });
        for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
        faces_.resize(start_.back());
        std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
        for (std::uint32_t f = 0; f < m.faces.size(); ++f) forCellsOf(f, [&](std::size_t c) { faces_[next[c]++] = f; });
    }

    struct Closest {
        Vec3 point;
        std::uint32_t face = 0;
        double distance = std::numeric_limits<double>::infinity();
    };

    /// Searches rings of cells outward until no nearer triangle can be in the next ring.
    Closest closest(const Vec3& p) const {
        Closest best;
        const Eigen::Array3i c = cellOf(p);
        const int maxRing = dims_.maxCoeff();
        // How far p lies inside its cell's walls: a point close to the surface usually finds its nearest
        // triangle nearer than that in its own cell, and the 26 round it need not be searched (a
        // triangle not listed in a searched cell lies wholly outside them). Outside the grid, nothing.
        const Vec3 low = box_.min + cell_ * c.cast<double>().matrix();
        const double inside =
            std::max(0.0, std::min((p - low).minCoeff(), (low + Vec3::Constant(cell_) - p).minCoeff()));
        for (int r = 0; r <= maxRing; ++r) {
            for (int x = c.x() - r; x <= c.x() + r; ++x)
                for (int y = c.y() - r; y <= c.y() + r; ++y)
                    for (int z = c.z() - r; z <= c.z() + r; ++z) {
                        if (std::max({std::abs(x - c.x()), std::abs(y - c.y()), std::abs(z - c.z())}) != r) continue;
                        if (x < 0 || y < 0 || z < 0 || x >= dims_.x() || y >= dims_.y() || z >= dims_.z()) continue;
                        for (std::uint32_t f : cellFaces(index(x, y, z))) {
                            const Face& t = m_.faces[f];
                            const auto q = geometry::closestPointOnTriangle(p, m_.positions[t[0]], m_.positions[t[1]],
                                                                            m_.positions[t[2]]);
                            const double d = (q.point - p).norm();
                            if (d < best.distance) best = {q.point, f, d};
                        }
                    }
            // Every point beyond ring r lies more than r cells and p's depth in its cell away.
            if (best.distance <= r * cell_ + inside) break;
        }
        return best;
    }

    /// The vector area of the input's faces whose centres lie within r of p, normalised: a normal that
    /// noise finer than r does not turn (a patch's vector area depends on its rim alone).
    Vec3 smoothNormal(const Vec3& p, double r) const {
        Vec3 sum = Vec3::Zero();
        const Eigen::Array3i lo = cellOf(p - Vec3::Constant(r)), hi = cellOf(p + Vec3::Constant(r));
        for (int x = lo.x(); x <= hi.x(); ++x)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int z = lo.z(); z <= hi.z(); ++z)
                    for (std::uint32_t f : cellFaces(index(x, y, z))) {
                        const Face& t = m_.faces[f];
                        const Vec3 c = (m_.positions[t[0]] + m_.positions[t[1]] + m_.positions[t[2]]) / 3;
                        // Counted once, in the cell that holds its centre.
                        if ((cellOf(c) != Eigen::Array3i(x, y, z)).any() || (c - p).norm() > r) continue;
                        sum += geometry::areaNormal(m_.positions[t[0]], m_.positions[t[1]], m_.positions[t[2]]);
                    }
        return sum.norm() > 0 ? Vec3(sum.normalized()) : Vec3::Zero();
    }

private:
    Eigen::Array3i cellOf(const Vec3& p) const {
        const Eigen::Array3i i = ((p - box_.min) / cell_).array().floor().cast<int>();
        return i.max(0).min(dims_ - 1);
    }
    std::size_t index(int x, int y, int z) const {
        return (static_cast<std::size_t>(z) * dims_.y() + y) * dims_.x() + x;
    }
    std::span<const std::uint32_t> cellFaces(std::size_t c) const {
        return {faces_.data() + start_[c], faces_.data() + start_[c + 1]};
    }

    static constexpr double kMaxCells = 16e6;
    const SurfaceMesh& m_;
    double cell_ = 0;
    geometry::Aabb box_;
    Eigen::Array3i dims_;
    std::vector<std::uint32_t> start_;  // cell c's faces are faces_[start_[c], start_[c + 1])
    std::vector<std::uint32_t> faces_;
};

/// The mesh being remeshed: faces die in place and are compacted at the end.
class Remesher {
public:
    Remesher(const SurfaceMesh& input, const RemeshOptions& options) : options_(options) {
        x_ = input.positions;
        faces_ = input.faces;
        faceAlive_.assign(faces_.size(), 1);
        liveFaces_ = faces_.size();
        around_.assign(x_.size(), {});
        for (std::uint32_t f = 0; f < faces_.size(); ++f)
            for (std::uint32_t v : faces_[f]) around_[v].push_back(f);
        feature_.assign(x_.size(), 0);
        boundary_.assign(x_.size(), 0);
        // Features: boundary edges and edges whose faces bend more than the feature angle.
        const double cosFeature = std::cos(options.featureAngle_deg * std::numbers::pi / 180);
        const MeshAdjacency adjacency = buildAdjacency(faces_);
        edgeCount_ = adjacency.edges.size();
        for (std::size_t e = 0; e < adjacency.edges.size(); ++e) {
            const auto faces = adjacency.facesOfEdge(e);
            bool isFeature = faces.size() != 2;
            if (!isFeature && options.featureAngle_deg > 0) {
                const Vec3 n0 = normalOf(faces[0]).normalized(), n1 = normalOf(faces[1]).normalized();
                isFeature = n0.dot(n1) < cosFeature;
            }
            if (faces.size() == 2) foldedEdges_ += normalOf(faces[0]).dot(normalOf(faces[1])) < 0;
            const Edge& edge = adjacency.edges[e];
            if (faces.size() == 1) boundary_[edge[0]] = boundary_[edge[1]] = 1;
            if (!isFeature) continue;
            featureEdges_.insert(edgeKey(edge[0], edge[1]));
            ++feature_[edge[0]], ++feature_[edge[1]];
        }
    }

    /// One pass: split, collapse, flip, relax (the caller projects onto the input afterwards).
    void pass(RemeshResult& stats) {
        const double l = options_.targetEdge_m, high = 4.0 / 3.0 * l, low = 4.0 / 5.0 * l;
        stats.splits += splitLongEdges(high);
        stats.collapses += collapseShortEdges(low, high);
        stats.flips += equaliseValences();
        relaxTangentially();
    }

    std::size_t featureEdgeCount() const { return featureEdges_.size(); }
    /// The input's edges whose two faces face apart, as a share of its edges.
    double foldedEdgeShare() const {
        return edgeCount_ > 0 ? static_cast<double>(foldedEdges_) / static_cast<double>(edgeCount_) : 0;
    }

    /// Smooths the mesh in place without shrinking it (Taubin 1995, "A signal processing approach to fair
    /// surface design": an umbrella step of 0.5 toward the neighbours' mean, then one of -0.53 away):
    /// on a rough input, whose faces fold against each other at every step of its noise, the passes'
    /// collapses are refused (they would turn faces too far), the count asked for is missed and the
    /// mending at the end collapses what is left. The passes project the vertices back onto the input.
    /// Boundary and feature vertices stay.
    void lowPass(int rounds) {
        std::vector<Vec3> next(x_.size());
        for (int step = 0; step < 2 * rounds; ++step) {
            const double weight = step % 2 == 0 ? 0.5 : -0.53;
            for (std::uint32_t v = 0; v < x_.size(); ++v) {
                next[v] = x_[v];
                if (feature_[v] > 0 || boundary_[v] != 0) continue;
                neighbours(v, scratchA_);
                if (scratchA_.empty()) continue;
                Vec3 mean = Vec3::Zero();
                for (std::uint32_t w : scratchA_) mean += x_[w];
                next[v] += weight * (mean / static_cast<double>(scratchA_.size()) - x_[v]);
            }
            x_.swap(next);
        }
    }
    std::size_t faceCount() const { return liveFaces_; }
    double targetEdge() const { return options_.targetEdge_m; }
    void setTargetEdge(double l) { options_.targetEdge_m = l; }
    std::size_t vertexCount() const { return x_.size(); }
    const Vec3& position(std::uint32_t v) const { return x_[v]; }

    /// Moves v to p unless that would turn one of its faces by more than about 35 degrees or shrink it
    /// to a sliver: projection onto a crease the input is too fine to call a feature, or relaxation
    /// past a neighbour, would otherwise fold thin triangles into it.
    bool moveIfFacesHold(std::uint32_t v, const Vec3& p) {
        for (std::uint32_t f : around_[v]) {
            const Face& g = faces_[f];
            const Vec3 before = normalOf(f);
            std::array<Vec3, 3> q{x_[g[0]], x_[g[1]], x_[g[2]]};
            for (int k = 0; k < 3; ++k)
                if (g[k] == v) q[k] = p;
            const Vec3 after = geometry::areaNormal(q[0], q[1], q[2]);
            if (after.norm() < 0.1 * before.norm() || after.normalized().dot(before.normalized()) < 0.8) return false;
        }
        x_[v] = p;
        return true;
    }
    bool onFeature(std::uint32_t v) const { return feature_[v] > 0; }

    /// The thin and folded triangles the passes leave where the input is noisier than the target edge
    /// (projection onto a surface that folds within one triangle sets its corners at odd heights), each
    /// mended by the first of: flipping its longest edge, collapsing its shortest, or moving one of its
    /// corners toward the centre of its neighbours, within `tolerance` of the input. A face is folded
    /// where it faces away from the input's normal smoothed over `radius`. Each edit folds fewer faces,
    /// or as few and raises the smallest angle, where it acts, so rounds end. Returns the edits.
    long mendSlivers(const SurfaceGrid& grid, double tolerance, double radius) {
        reference_.assign(x_.size(), Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
        grid_ = &grid;
        radius_ = radius;
        long edits = 0;
        const double high = 1.5 * options_.targetEdge_m;
        for (int round = 0; round < 20; ++round) {
            long thisRound = 0;
            for (std::uint32_t f = 0; f < faces_.size(); ++f) {
                if (!faceAlive_[f] || (sineOf(f) >= kMendSine && !folded(f))) continue;
                if (flipLongestEdge(f) || collapseShortestEdge(f, high) || moveACorner(f, tolerance)) ++thisRound;
            }
            edits += thisRound;
            if (thisRound == 0) break;
        }
        return edits;
    }

    /// The live mesh, compacted.
    SurfaceMesh compacted() const {
        SurfaceMesh out;
        std::vector<std::uint32_t> index(x_.size(), ~std::uint32_t{0});
        for (std::uint32_t f = 0; f < faces_.size(); ++f) {
            if (!faceAlive_[f]) continue;
            Face g;
            for (int k = 0; k < 3; ++k) {
                std::uint32_t& i = index[faces_[f][k]];
                if (i == ~std::uint32_t{0}) {
                    i = static_cast<std::uint32_t>(out.positions.size());
                    out.positions.push_back(x_[faces_[f][k]]);
                }
                g[k] = i;
            }
            out.faces.push_back(g);
        }
        return out;
    }

private:
    Vec3 normalOf(std::uint32_t f) const {
        return geometry::areaNormal(x_[faces_[f][0]], x_[faces_[f][1]], x_[faces_[f][2]]);
    }
    bool isFeature(std::uint32_t a, std::uint32_t b) const { return featureEdges_.count(edgeKey(a, b)) != 0; }
    double sineOf(std::uint32_t f) const {
        return smallestAngleSine(x_[faces_[f][0]], x_[faces_[f][1]], x_[faces_[f][2]]);
    }
    /// The input's smoothed normal near v (mendSlivers).
    const Vec3& reference(std::uint32_t v) {
        if (std::isnan(reference_[v].x())) reference_[v] = grid_->smoothNormal(x_[v], radius_);
        return reference_[v];
    }
    /// Whether a face of normal n at corner v faces away from the surface (by more than 60 degrees).
    bool facesAway(const Vec3& n, std::uint32_t v) { return n.norm() == 0 || n.normalized().dot(reference(v)) < 0.5; }
    bool folded(std::uint32_t f) { return facesAway(normalOf(f), faces_[f][0]); }

    /// How good a few faces are: fewer folded first, then a larger smallest angle.
    struct Quality {
        int folded = 0;
        double sine = 1;
        bool betterThan(const Quality& o) const { return folded != o.folded ? folded < o.folded : sine > o.sine; }
        void add(const Vec3& a, const Vec3& b, const Vec3& c, bool away) {
            folded += away;
            sine = std::min(sine, smallestAngleSine(a, b, c));
        }
    };
    /// The quality of v's faces with v at p.
    Quality qualityAround(std::uint32_t v, const Vec3& p) {
        Quality q;
        for (std::uint32_t f : around_[v]) {
            std::array<Vec3, 3> c{x_[faces_[f][0]], x_[faces_[f][1]], x_[faces_[f][2]]};
            for (int k = 0; k < 3; ++k)
                if (faces_[f][k] == v) c[k] = p;
            q.add(c[0], c[1], c[2], facesAway(geometry::areaNormal(c[0], c[1], c[2]), v));
        }
        return q;
    }

    /// The edge opposite f's largest angle flipped, where that makes the pair better.
    bool flipLongestEdge(std::uint32_t f) {
        int k = 0;
        double longest = 0;
        for (int i = 0; i < 3; ++i)
            if (const double l = (x_[faces_[f][i]] - x_[faces_[f][(i + 1) % 3]]).norm(); l > longest)
                longest = l, k = i;
        const std::uint32_t a = faces_[f][k], b = faces_[f][(k + 1) % 3];
        const auto pair = flippable(f, a, b);
        if (!pair) return false;
        const std::uint32_t c = pair->c, d = pair->d;
        Quality before, after;
        const auto away = [&](const Vec3& n) { return facesAway(n, a) || facesAway(n, b); };
        before.add(x_[a], x_[b], x_[c], away(normalOf(f)));
        before.add(x_[b], x_[a], x_[d], away(normalOf(pair->f2)));
        after.add(x_[a], x_[d], x_[c], away(geometry::areaNormal(x_[a], x_[d], x_[c])));
        after.add(x_[d], x_[b], x_[c], away(geometry::areaNormal(x_[d], x_[b], x_[c])));
        if (!after.betterThan(before)) return false;
        flip(f, a, b, *pair);
        return true;
    }

    /// f's shortest edge collapsed (either way), as the passes collapse, up to edges of `high`; never
    /// on a feature or boundary (that would take a corner of it with the edge, however short).
    bool collapseShortestEdge(std::uint32_t f, double high) {
        int k = 0;
        double shortest = std::numeric_limits<double>::infinity();
        for (int i = 0; i < 3; ++i)
            if (const double l = (x_[faces_[f][i]] - x_[faces_[f][(i + 1) % 3]]).norm(); l < shortest)
                shortest = l, k = i;
        const std::uint32_t a = faces_[f][k], b = faces_[f][(k + 1) % 3];
        if (feature_[a] > 0 || feature_[b] > 0 || onBoundary(a) || onBoundary(b)) return false;
        return tryCollapse(a, b, high) || tryCollapse(b, a, high);
    }

    /// One of f's free corners moved to (or halfway to) the centre of its neighbours, off the input's
    /// noise but within `tolerance` of it, where that makes its faces better (a smart Laplacian step:
    /// Freitag, Jones and Plassmann 1995).
    bool moveACorner(std::uint32_t f, double tolerance) {
        for (const std::uint32_t v : faces_[f]) {
            if (feature_[v] > 0 || onBoundary(v)) continue;
            neighbours(v, scratchD_);
            Vec3 centre = Vec3::Zero();
            for (std::uint32_t w : scratchD_) centre += x_[w];
            centre /= static_cast<double>(scratchD_.size());
            const Quality before = qualityAround(v, x_[v]);
            for (const double step : {1.0, 0.5}) {
                Vec3 p = x_[v] + step * (centre - x_[v]);
                const auto near = grid_->closest(p);
                if (near.distance > tolerance) p = near.point + (p - near.point) * (tolerance / near.distance);
                if (!qualityAround(v, p).betterThan(before)) continue;
                x_[v] = p;
                return true;
            }
        }
        return false;
    }

    std::size_t facesOfEdgeCount(std::uint32_t a, std::uint32_t b) const {
        facesOfEdge(a, b, scratchE_);
        return scratchE_.size();
    }
    void facesOfEdge(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>& out) const {
        out.clear();
        for (std::uint32_t f : around_[a])
            if (faces_[f][0] == b || faces_[f][1] == b || faces_[f][2] == b) out.push_back(f);
    }
    void neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const {
        out.clear();
        for (std::uint32_t f : around_[v])
            for (std::uint32_t w : faces_[f])
                if (w != v && std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
    }
    /// The number of edges at v: faces round an interior vertex, one more on a boundary.
    int valence(std::uint32_t v) const {
        neighbours(v, scratchD_);
        return static_cast<int>(scratchD_.size());
    }
    /// Kept through every edit: a split of a boundary edge makes a boundary vertex, a boundary vertex
    /// collapses only along its boundary (boundary edges are features), and flips leave boundaries alone.
    bool onBoundary(std::uint32_t v) const { return boundary_[v] != 0; }
    void replaceInAround(std::uint32_t v, std::uint32_t from, std::uint32_t to) {
        std::replace(around_[v].begin(), around_[v].end(), from, to);
    }
    void removeFromAround(std::uint32_t v, std::uint32_t f) {
        auto& a = around_[v];
        a.erase(std::remove(a.begin(), a.end(), f), a.end());
    }

    /// Every edge longer than `high` split at its middle, until none is: each face's longest edge first
    /// (longest-edge bisection), which keeps the angles of the pieces bounded; splitting whichever long
    /// edge came first made slivers that asked for ever more splits.
    long splitLongEdges(double high) {
        long count = 0;
        for (std::uint32_t f = 0; f < faces_.size(); ++f) {  // faces appended by splits are met too
            while (faceAlive_[f]) {
                int longest = 0;
                double length = 0;
                for (int k = 0; k < 3; ++k)
                    if (const double l = (x_[faces_[f][k]] - x_[faces_[f][(k + 1) % 3]]).norm(); l > length)
                        longest = k, length = l;
                if (length <= high) break;
                split(faces_[f][longest], faces_[f][(longest + 1) % 3]);
                ++count;
            }
        }
        return count;
    }

    void split(std::uint32_t a, std::uint32_t b) {
        const auto m = static_cast<std::uint32_t>(x_.size());
        x_.push_back(0.5 * (x_[a] + x_[b]));
        around_.emplace_back();
        const bool feature = isFeature(a, b);
        feature_.push_back(feature ? 2 : 0);
        boundary_.push_back(facesOfEdgeCount(a, b) == 1);
        if (feature) {
            featureEdges_.erase(edgeKey(a, b));
            featureEdges_.insert(edgeKey(a, m));
            featureEdges_.insert(edgeKey(m, b));
        }
        facesOfEdge(a, b, scratchC_);
        for (std::uint32_t f : scratchC_) {
            Face face = faces_[f];
            int k = 0;
            while (!((face[k] == a && face[(k + 1) % 3] == b) || (face[k] == b && face[(k + 1) % 3] == a))) ++k;
            const std::uint32_t p = face[k], q = face[(k + 1) % 3], c = face[(k + 2) % 3];
            faces_[f] = {p, m, c};
            const auto g = static_cast<std::uint32_t>(faces_.size());
            faces_.push_back({m, q, c});
            faceAlive_.push_back(1);
            ++liveFaces_;
            replaceInAround(q, f, g);
            around_[c].push_back(g);
            around_[m].push_back(f);
            around_[m].push_back(g);
        }
    }

    /// Edges shorter than `low` collapsed, unless that would make an edge longer than `high`, fold a
    /// face, pinch the surface or move a feature.
    long collapseShortEdges(double low, double high) {
        // One sweep, as Botsch and Kobbelt do: an edge left short now is met again in the next pass.
        long count = 0;
        for (std::uint32_t f = 0; f < faces_.size(); ++f) {
            if (!faceAlive_[f]) continue;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = faces_[f][k], b = faces_[f][(k + 1) % 3];
                if ((x_[a] - x_[b]).norm() >= low) continue;
                if (tryCollapse(a, b, high) || tryCollapse(b, a, high)) {
                    ++count;
                    break;  // this face is gone
                }
            }
        }
        return count;
    }

    /// Collapses a into b; false (nothing changed) when it may not.
    bool tryCollapse(std::uint32_t a, std::uint32_t b, double high) {
        // A feature vertex goes only along its feature line, into its neighbour on it, which stays.
        const bool alongFeature = feature_[a] > 0;
        if (alongFeature && !(feature_[a] == 2 && isFeature(a, b))) return false;
        const Vec3 target = alongFeature || feature_[b] > 0 ? x_[b] : Vec3(0.5 * (x_[a] + x_[b]));
        // Link condition: a and b share exactly the neighbours opposite their edge.
        facesOfEdge(a, b, scratchC_);
        if (scratchC_.empty()) return false;
        neighbours(a, scratchA_);
        neighbours(b, scratchB_);
        int shared = 0;
        for (std::uint32_t w : scratchA_)
            if (std::find(scratchB_.begin(), scratchB_.end(), w) != scratchB_.end()) ++shared;
        if (shared != static_cast<int>(scratchC_.size())) return false;
        // Nor round a corner of its feature line: a's feature edges must run on nearly straight.
        if (alongFeature)
            for (std::uint32_t w : scratchA_)
                if (w != b && isFeature(a, w) && (x_[a] - x_[w]).normalized().dot((x_[b] - x_[a]).normalized()) < 0.9)
                    return false;
        // An interior edge between two boundary vertices would pinch the surface.
        if (scratchC_.size() == 2 && onBoundary(a) && onBoundary(b)) return false;
        // Every vertex keeps three neighbours at least: b takes a's, and each vertex opposite the edge
        // loses one. (A valence-3 vertex may go: it is the apex of the caps that valences leave.)
        if (scratchA_.size() + scratchB_.size() - static_cast<std::size_t>(shared) - 2 < 3) return false;
        for (std::uint32_t f : scratchC_)
            for (std::uint32_t w : faces_[f])
                if (w != a && w != b && valence(w) <= 3) return false;
        // No edge longer than `high`, no face turned over or made degenerate.
        for (std::uint32_t w : scratchA_)
            if (w != b && (x_[w] - target).norm() > high) return false;
        for (std::uint32_t v : {a, b})
            for (std::uint32_t f : around_[v]) {
                if (std::find(scratchC_.begin(), scratchC_.end(), f) != scratchC_.end()) continue;
                const Face g0 = faces_[f];
                Face g = g0;
                const Vec3 before = geometry::areaNormal(x_[g[0]], x_[g[1]], x_[g[2]]);
                for (std::uint32_t& c : g)
                    if (c == a || c == b) c = ~std::uint32_t{0};
                std::array<Vec3, 3> p;
                for (int k = 0; k < 3; ++k) p[k] = g[k] == ~std::uint32_t{0} ? target : x_[g[k]];
                const Vec3 after = geometry::areaNormal(p[0], p[1], p[2]);
                if (after.norm() < 1e-12 * before.norm() || after.normalized().dot(before.normalized()) < 0.8)
                    return false;
                // Nor a new sliver: thin triangles left by collapses on a fine input outlived every flip.
                const double was = smallestAngleSine(x_[g0[0]], x_[g0[1]], x_[g0[2]]);
                if (smallestAngleSine(p[0], p[1], p[2]) < std::min(kSliverSine, was)) return false;
            }
        // Do it: the edge's faces go, a's other faces take b, a's feature edges become b's.
        for (std::uint32_t f : scratchC_) {
            faceAlive_[f] = 0;
            --liveFaces_;
            for (std::uint32_t v : faces_[f]) removeFromAround(v, f);
        }
        if (isFeature(a, b)) {
            featureEdges_.erase(edgeKey(a, b));
            --feature_[b];
        }
        for (std::uint32_t w : scratchA_) {
            if (w == b || !isFeature(a, w)) continue;
            featureEdges_.erase(edgeKey(a, w));
            --feature_[w];
            if (!isFeature(b, w)) {
                featureEdges_.insert(edgeKey(b, w));
                ++feature_[b];
                ++feature_[w];
            }
        }
        for (std::uint32_t f : around_[a]) {
            for (std::uint32_t& c : faces_[f])
                if (c == a) c = b;
            around_[b].push_back(f);
        }
        around_[a].clear();
        feature_[a] = 0;
        x_[b] = target;
        return true;
    }

    /// Flips that bring the four vertices' valences nearer six (four on a boundary).
    long equaliseValences() {
        long count = 0;
        for (std::uint32_t f = 0; f < faces_.size(); ++f) {
            if (!faceAlive_[f]) continue;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = faces_[f][k], b = faces_[f][(k + 1) % 3];
                if (tryFlip(f, a, b)) {
                    ++count;
                    break;
                }
            }
        }
        return count;
    }

    /// The faces on either side of edge a -> b of f1 and their far corners, where the edge may flip: two
    /// faces, not a feature, and no edge c-d already.
    struct FlipPair {
        std::uint32_t f2 = 0, c = 0, d = 0;
    };
    std::optional<FlipPair> flippable(std::uint32_t f1, std::uint32_t a, std::uint32_t b) {
        if (isFeature(a, b)) return std::nullopt;
        facesOfEdge(a, b, scratchC_);
        if (scratchC_.size() != 2) return std::nullopt;
        FlipPair p;
        p.f2 = scratchC_[0] == f1 ? scratchC_[1] : scratchC_[0];
        for (std::uint32_t v : faces_[f1])  // runs a -> b
            if (v != a && v != b) p.c = v;
        for (std::uint32_t v : faces_[p.f2])  // runs b -> a
            if (v != a && v != b) p.d = v;
        if (p.c == p.d) return std::nullopt;
        neighbours(p.c, scratchA_);
        if (std::find(scratchA_.begin(), scratchA_.end(), p.d) != scratchA_.end()) return std::nullopt;
        return p;
    }
    void flip(std::uint32_t f1, std::uint32_t a, std::uint32_t b, const FlipPair& p) {
        faces_[f1] = {a, p.d, p.c};
        faces_[p.f2] = {p.d, b, p.c};
        removeFromAround(b, f1);
        removeFromAround(a, p.f2);
        around_[p.d].push_back(f1);
        around_[p.c].push_back(p.f2);
    }

    bool tryFlip(std::uint32_t f1, std::uint32_t a, std::uint32_t b) {
        const auto pair = flippable(f1, a, b);
        if (!pair) return false;
        const std::uint32_t f2 = pair->f2, c = pair->c, d = pair->d;
        const auto target = [&](std::uint32_t v) { return onBoundary(v) ? 4 : 6; };
        const int va = valence(a), vb = valence(b), vc = valence(c), vd = valence(d);
        const int ta = target(a), tb = target(b), tc = target(c), td = target(d);
        const int before = std::abs(va - ta) + std::abs(vb - tb) + std::abs(vc - tc) + std::abs(vd - td);
        const int after = std::abs(va - 1 - ta) + std::abs(vb - 1 - tb) + std::abs(vc + 1 - tc) + std::abs(vd + 1 - td);
        if (after >= before) return false;
        // Only across nearly flat edges, and never into a folded pair.
        const Vec3 n = (normalOf(f1).normalized() + normalOf(f2).normalized()).normalized();
        const Vec3 m1 = geometry::areaNormal(x_[a], x_[d], x_[c]), m2 = geometry::areaNormal(x_[d], x_[b], x_[c]);
        if (m1.norm() < 1e-14 || m2.norm() < 1e-14) return false;
        if (m1.normalized().dot(n) < 0.5 || m2.normalized().dot(n) < 0.5) return false;
        const double was = std::min(smallestAngleSine(x_[a], x_[b], x_[c]), smallestAngleSine(x_[b], x_[a], x_[d]));
        if (std::min(smallestAngleSine(x_[a], x_[d], x_[c]), smallestAngleSine(x_[d], x_[b], x_[c])) <
            std::min(kSliverSine, was))
            return false;
        flip(f1, a, b, *pair);
        return true;
    }

    /// Each free vertex toward the area-weighted centre of its faces, within its tangent plane (in
    /// turn, each move kept only where its faces hold).
    void relaxTangentially() {
        for (std::uint32_t v = 0; v < x_.size(); ++v) {
            if (around_[v].empty() || feature_[v] > 0) continue;
            Vec3 centre = Vec3::Zero(), normal = Vec3::Zero();
            double area = 0;
            for (std::uint32_t f : around_[v]) {
                const Face& g = faces_[f];
                const Vec3 n = normalOf(f);
                const double a = 0.5 * n.norm();
                centre += a * (x_[g[0]] + x_[g[1]] + x_[g[2]]) / 3;
                normal += n;
                area += a;
            }
            if (area <= 0 || normal.norm() == 0) continue;
            centre /= area;
            normal.normalize();
            const Vec3 move = centre - x_[v];
            moveIfFacesHold(v, x_[v] + move - normal.dot(move) * normal);
        }
    }

    RemeshOptions options_;
    std::size_t liveFaces_ = 0;
    std::size_t edgeCount_ = 0, foldedEdges_ = 0;  // of the input
    // mendSlivers: the input, the radius its normal is smoothed over, and that normal by vertex.
    const SurfaceGrid* grid_ = nullptr;
    double radius_ = 0;
    std::vector<Vec3> reference_;
    std::vector<Vec3> x_;
    std::vector<Face> faces_;
    std::vector<std::uint8_t> faceAlive_;
    std::vector<std::vector<std::uint32_t>> around_;
    std::vector<std::uint8_t> feature_;  // per vertex: how many feature edges it is on
    std::vector<std::uint8_t> boundary_;
    std::unordered_set<std::uint64_t> featureEdges_;
    mutable std::vector<std::uint32_t> scratchA_, scratchB_, scratchD_, scratchE_;
    std::vector<std::uint32_t> scratchC_;
};

}  // namespace

namespace {

/// Each connected piece of `m` in the part most of its faces lie nearest to: remeshing never joins
/// pieces, and a face near where two parts touch may lie nearest to the other one.
std::vector<std::uint32_t> partsByPiece(const SurfaceMesh& m, const std::vector<std::uint32_t>& nearestPart) {
    const std::vector<std::uint32_t> piece = facePieces(buildAdjacency(m.faces), false);
    std::unordered_map<std::uint64_t, std::size_t> votes;  // (piece, part) -> faces
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) ++votes[(std::uint64_t{piece[f]} << 32) | nearestPart[f]];
    std::unordered_map<std::uint32_t, std::pair<std::uint32_t, std::size_t>> winner;  // piece -> (part, votes)
    for (const auto& [key, count] : votes) {
        auto& w = winner[static_cast<std::uint32_t>(key >> 32)];
        const auto part = static_cast<std::uint32_t>(key & 0xffffffffu);
        if (count > w.second || (count == w.second && part < w.first)) w = {part, count};
    }
    std::vector<std::uint32_t> parts(m.faces.size());
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) parts[f] = winner[piece[f]].first;
    return parts;
}

}  // namespace

double targetEdgeForTriangles(const SurfaceMesh& mesh, std::size_t triangles) {
    // An equilateral triangle of edge L has area sqrt(3)/4 L^2. Remeshed edges settle between 4/5 and
    // 4/3 of the target, longer than it on average: 0.9 of that length gives the count asked for (the
    // heart at 100,000 triangles remeshed for 20,000 gave 16,500 without it).
    const double equilateral =
        std::sqrt(4 * surfaceArea(mesh) / (std::sqrt(3.0) * static_cast<double>(std::max<std::size_t>(triangles, 1))));
    return 0.9 * equilateral;
}

Result<RemeshResult, std::string> remeshIsotropic(const SurfaceMesh& input, const RemeshOptions& options) {
    if (!(options.targetEdge_m > 0) || !std::isfinite(options.targetEdge_m))
        return unexpected(std::string("the target edge length must be a positive number of metres"));
    if (input.faces.empty()) return unexpected(std::string("the mesh has no faces"));
    const MeshAdjacency adjacency = buildAdjacency(input.faces);
    for (std::size_t e = 0; e < adjacency.edges.size(); ++e)
        if (adjacency.facesOfEdge(e).size() > 2)
            return unexpected(std::string("the mesh has edges on three or more faces: repair it first (--repair)"));

    Remesher remesher(input, options);
    RemeshResult result;
    result.featureEdges = remesher.featureEdgeCount();
    result.foldedInputShare = remesher.foldedEdgeShare();
    result.smoothedFirst = result.foldedInputShare > kRoughInput;
    if (result.smoothedFirst) remesher.lowPass(kRoughInputRounds);
    // Cells of two input edges hold a few triangles each; of a quarter of the edge asked for when that is
    // larger, so that the smooth normal's search over cells (twice that edge round a point) stays short.
    const SurfaceGrid grid(input, 2 * std::max(meanEdgeLength(input), options.targetEdge_m / 4));
    for (int it = 0; it < options.iterations; ++it) {
        remesher.pass(result);
        // Relaxation moves vertices off a curved surface: each pass ends with them put back on it.
        for (std::uint32_t v = 0; v < remesher.vertexCount(); ++v)
            if (!remesher.onFeature(v)) remesher.moveIfFacesHold(v, grid.closest(remesher.position(v)).point);
        // A count asked for steers the edge length, pass by pass: a noisy input's area, from which the
        // first length was worked out, is larger than the remeshed surface's (a jittered heart asked for
        // 20,000 triangles gave 14,606), and the count goes as the inverse square of the edge.
        if (options.targetTriangles > 0 && it + 2 < options.iterations) {
            const double ratio =
                static_cast<double>(remesher.faceCount()) / static_cast<double>(options.targetTriangles);
            remesher.setTargetEdge(remesher.targetEdge() * std::clamp(std::sqrt(ratio), 0.8, 1.25));
        }
    }
    result.targetEdge_m = remesher.targetEdge();
    // Off the input by at most half an edge, and never more than 0.5% of the model's size.
    geometry::Aabb box;
    for (const Vec3& p : input.positions) box.grow(p);
    result.sliversMended = remesher.mendSlivers(grid, std::min(0.5 * result.targetEdge_m, 0.005 * box.extent().norm()),
                                                2 * result.targetEdge_m);

    result.mesh = remesher.compacted();
    SurfaceMesh& out = result.mesh;
    // Valence flips leave a few thin triangles where the valences balance: flips that raise the smallest
    // angle (the Delaunay criterion) finish them, across nearly flat edges only, so features stay.
    out.edges = edgesOfFaces(out.faces);
    result.flips += improveByEdgeFlips(out, {.maxPasses = 10, .minNormalCosine = 0.9});
    // UVs from the input face nearest each new face's centre, through that face's affine map, so that a
    // face across a texture seam takes one side's coordinates rather than a mix.
    out.uvs.resize(out.faces.size());
    std::vector<std::uint32_t> nearestPart(out.faces.size(), 0);
    double sum = 0;
    std::size_t samples = 0;
    for (std::size_t f = 0; f < out.faces.size(); ++f) {
        const Face& g = out.faces[f];
        const Vec3 centre = (out.positions[g[0]] + out.positions[g[1]] + out.positions[g[2]]) / 3;
        const auto near = grid.closest(centre);
        result.distanceMax_m = std::max(result.distanceMax_m, near.distance);
        sum += near.distance;
        ++samples;
        nearestPart[f] = input.partOf(near.face);
        const Face& t = input.faces[near.face];
        const Vec3 &p0 = input.positions[t[0]], &p1 = input.positions[t[1]], &p2 = input.positions[t[2]];
        const Vec3 e1 = p1 - p0, e2 = p2 - p0;
        const double a11 = e1.dot(e1), a12 = e1.dot(e2), a22 = e2.dot(e2), det = a11 * a22 - a12 * a12;
        for (int k = 0; k < 3; ++k) {
            if (input.uvs.size() != input.faces.size() || std::abs(det) < 1e-30) {
                out.uvs[f][k] = Vec2::Zero();
                continue;
            }
            const Vec3 r = out.positions[g[k]] - p0;
            const double b1 = r.dot(e1), b2 = r.dot(e2);
            const double s = (a22 * b1 - a12 * b2) / det, u = (a11 * b2 - a12 * b1) / det;
            const FaceUvs& uv = input.uvs[near.face];
            out.uvs[f][k] = (1 - s - u) * uv[0] + s * uv[1] + u * uv[2];
        }
    }
    for (const Vec3& p : out.positions) {
        const double d = grid.closest(p).distance;
        result.distanceMax_m = std::max(result.distanceMax_m, d);
        sum += d;
        ++samples;
    }
    result.distanceMean_m = samples > 0 ? sum / static_cast<double>(samples) : 0;
    if (input.hasParts()) {
        out.partNames = input.partNames;
        out.faceParts = partsByPiece(out, nearestPart);
        // Each part's faces together, in part order: a written file then has one group per part.
        std::vector<std::size_t> order(out.faces.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return out.faceParts[a] < out.faceParts[b]; });
        SurfaceMesh sorted;
        for (std::size_t f : order) {
            sorted.faces.push_back(out.faces[f]);
            sorted.uvs.push_back(out.uvs[f]);
            sorted.faceParts.push_back(out.faceParts[f]);
        }
        out.faces = std::move(sorted.faces);
        out.uvs = std::move(sorted.uvs);
        out.faceParts = std::move(sorted.faceParts);
    }
    out.edges = edgesOfFaces(out.faces);
    computeFaceNormals(out);
    return result;
}

}  // namespace hapticut::mesh
