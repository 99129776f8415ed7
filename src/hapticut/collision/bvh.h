// Bounding volume hierarchy over the triangles of a deforming mesh: build, linear-time refit, faces
// added and changed by cuts in time proportional to the tree's depth, and closest-point, first-hit
// and radius queries that never allocate. A binary tree is built and kept up to date; queries walk
// the same tree collapsed to four boxes a node (wide_node.h), half as deep and tested four at a time.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "hapticut/collision/wide_node.h"
#include "hapticut/geometry/aabb.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::collision {

/// The surface as queries see it: the current (deformed) positions and the faces.
struct SurfaceView {
    std::span<const Vec3> positions;
    std::span<const mesh::Face> faces;
};

struct SurfacePoint {
    std::uint32_t face = 0;
    Vec3 point = Vec3::Zero();
    Vec3 bary = Vec3::Zero();
    double distance = 0;  // m, from the query point
};

struct SegmentHit {
    std::uint32_t face = 0;
    double t = 0;  // fraction along the segment
    Vec3 point = Vec3::Zero();
    Vec3 bary = Vec3::Zero();
};

class Bvh {
public:
    static constexpr int kLeafSize = 4;

    /// Every leaf's box grows by `margin_m` on each side from the next build or refit on. A tree whose
    /// boxes were computed from reference positions then answers every query exactly for any surface
    /// whose vertices lie within the margin of those: a vertex that moves less than the margin needs no
    /// refit (the enlarged boxes of Catto's dynamic tree in Box2D, applied to a tree refitted as the
    /// mesh deforms, after van den Bergen 1997).
    void setMargin(double margin_m) { margin_m_ = margin_m; }
    double margin() const { return margin_m_; }

    void build(const SurfaceView& surface);
    /// Recomputes every box bottom-up from the current positions, in time linear in the faces.
    void refit(const SurfaceView& surface);
    /// Recomputes only the boxes of the leaves holding `faces` (repeats allowed) and of their
    /// ancestors, in time proportional to those: for a deformation confined to a region. The other
    /// faces must not have moved since the last refit. Never allocates.
    void refitFaces(const SurfaceView& surface, std::span<const std::uint32_t> faces);
    /// After a topology edit: faces appended since the last call join the leaf whose box grows least
    /// (a face split off another lies inside its box), and the listed faces whose corners changed
    /// grow their leaf's box and its ancestors', so every query stays exact before the next refit.
    /// Costs the tree's depth per face. Once the added faces are half as many as the built ones the
    /// tree is rebuilt, which costs O(n log n).
    void facesChanged(const SurfaceView& surface, std::span<const std::uint32_t> changed = {});

    std::optional<SurfacePoint> closestPoint(const SurfaceView& surface, const Vec3& p,
                                             double max_distance = std::numeric_limits<double>::infinity()) const;
    /// The first face the segment from -> to crosses, from either side.
    std::optional<SegmentHit> firstHit(const SurfaceView& surface, const Vec3& from, const Vec3& to) const;
    /// How many faces the segment crosses: odd means the end points are on different sides of a closed surface.
    int countCrossings(const SurfaceView& surface, const Vec3& from, const Vec3& to) const;
    /// Faces with a point within `radius` of p, appended to `out` (cleared first).
    void facesWithinRadius(const SurfaceView& surface, const Vec3& p, double radius,
                           std::vector<std::uint32_t>& out) const;

    std::size_t nodeCount() const { return nodes_.size(); }
    /// Faces added since the last build, held in chains at the leaves.
    std::size_t addedFaces() const { return addedFaces_; }

private:
    static constexpr std::uint32_t kNone = 0xffffffffu;
    struct Node {
        geometry::Aabb box;
        std::uint32_t start = 0, count = 0;  // leaf: faceOrder_[start, start + count)
        std::uint32_t right = 0;             // inner: the left child is the next node (preorder)
        std::uint32_t parent = kNone;
        std::uint32_t added = kNone;  // leaf: the first face added since the build (see addedNext_)
        std::uint32_t depth = 0;      // the root's is 0
    };
    static constexpr int kMaxDepth = 64;
    // A wide node pops one entry and pushes up to four, on a tree at most kMaxDepth / 2 wide nodes deep.
    static constexpr int kWideStack = 2 * kMaxDepth;

    std::uint32_t buildNode(const SurfaceView& s, std::uint32_t start, std::uint32_t count,
                            std::vector<Vec3>& centroids, int depth);
    geometry::Aabb faceBox(const SurfaceView& s, std::uint32_t f) const;
    /// Node i's box from its faces (a leaf) or its children (an inner node).
    void recomputeBox(const SurfaceView& s, std::size_t i);
    /// Collapses the binary tree under `node` into wide node `wide`: its lanes are the node's children,
    /// or their children where those are inner nodes.
    void collapse(std::uint32_t node, std::uint32_t wide);
    /// Copies node i's box into the lane that holds it in the wide tree, if one does (recomputeBox
    /// leaves that to its callers).
    void publish(std::size_t i);
    /// The largest coordinate magnitude of any box: what the wide tree's rounding is relative to.
    double boxScale() const;
    /// Visits the faces of every leaf whose lane `lanes` accepts, as bits of a wide node.
    template <class Lanes, class Visit>
    void traverse(Lanes&& lanes, Visit&& visit) const;
    /// Visits the faces of the leaves whose lanes `lanes` accepts, nearest first by the key it gives each
    /// lane (a squared distance, or where a segment enters), skipping an entry whose key `reachable`
    /// no longer accepts when it comes off the stack (a hit found since is nearer).
    template <class Lanes, class Reachable, class Visit>
    void traverseNearestFirst(Lanes&& lanes, Reachable&& reachable, Visit&& visit) const;
    template <class Visit>
    void visitLeaf(const Node& leaf, Visit&& visit) const;
    void insertFace(const SurfaceView& s, std::uint32_t f);
    void growToContain(std::uint32_t node, const geometry::Aabb& box);

    std::vector<Node> nodes_;
    std::vector<std::uint32_t> faceOrder_;
    std::vector<std::uint32_t> leafOf_;     // the leaf holding each face
    std::vector<std::uint32_t> addedNext_;  // the next added face in the same leaf's chain, per face
    // refitFaces: per node, the call that last marked it for recomputing; the nodes it marked, and
    // the same deepest first (both reserved for every node at the build).
    std::vector<std::uint32_t> staleMark_, marked_, markedDeepestFirst_;
    std::vector<WideNode> wide_;
    std::vector<std::uint32_t> laneOf_;  // per binary node: 4 · wide node + lane holding its box, or kNone
    std::vector<std::array<std::uint32_t, 4>> laneSources_;  // per wide node: the binary node in each lane
    std::uint32_t refitCall_ = 0;
    std::size_t builtFaces_ = 0, addedFaces_ = 0;
    double margin_m_ = 0;
};

}  // namespace hapticut::collision
