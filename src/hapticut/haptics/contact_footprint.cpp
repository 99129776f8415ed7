// A tool tip's footprint on the surface.
#include "hapticut/haptics/contact_footprint.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "hapticut/common/reserve.h"
#include "hapticut/haptics/proxy.h"

namespace hapticut::haptics {

namespace {

/// How deep a face is split at most: a face 4,000 times larger than the tip is still resolved.
constexpr int kMaxSplits = 12;
/// Faces looked at per footprint at most: every loaded face and the ring round them.
constexpr std::size_t kMaxQueuedFaces = 4 * physics::kMaxContactNodes;

struct Piece {
    std::array<Vec3, 3> corner_m;  // where its corners are
    std::array<Vec3, 3> bary;      // and where on the face
    int depth = 0;
};

}  // namespace

void ContactFootprint::fitTo(std::size_t nodes, std::size_t faces) {
    // With room to grow, like the organ's arrays, so that cuts seldom reallocate these.
    if (nodes > nodeStamp_.size()) {
        nodeStamp_.resize(roomToGrow(nodes), 0);
        nodeSlot_.resize(nodeStamp_.size(), 0);
    }
    if (faces > faceStamp_.size()) faceStamp_.resize(roomToGrow(faces), 0);
    queue_.reserve(kMaxQueuedFaces);
    nodes_.resize(physics::kMaxContactNodes);
    loads_.resize(physics::kMaxContactNodes);
}

Vec3 ContactFootprint::integrateFace(const collision::SurfaceView& s, std::uint32_t face, const Vec3& centre_m,
                                     double radius_m) const noexcept {
    const mesh::Face& f = s.faces[face];
    const double leafSize_m = radius_m / 3;
    {
        // Most faces of a mesh finer than the tip need no split: the same test and rule as a piece at
        // depth 0 below, without moving the piece through the stack (a footprint on a million-triangle
        // organ integrates some 8,000 faces).
        const Vec3 &a = s.positions[f[0]], &b = s.positions[f[1]], &c = s.positions[f[2]];
        const Vec3 g = (a + b + c) / 3;
        // One root instead of three: the root of the largest square is the largest root, to the bit.
        const double reach_m =
            std::sqrt(std::max({(a - g).squaredNorm(), (b - g).squaredNorm(), (c - g).squaredNorm()}));
        const double distance_m = (g - centre_m).norm();
        if (distance_m - reach_m >= radius_m) return Vec3::Zero();
        if (2 * reach_m <= leafSize_m) {
            const double area_m2 = 0.5 * (b - a).cross(c - a).norm();
            return tipPressure(distance_m / radius_m) * area_m2 * Vec3::Ones() / 3;
        }
    }
    // Depth-first, four children per split: the stack never holds more than 3 per level, plus one.
    std::array<Piece, 3 * kMaxSplits + 4> stack;
    std::size_t top = 0;
    stack[top++] = Piece{
        {s.positions[f[0]], s.positions[f[1]], s.positions[f[2]]}, {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()}, 0};
    Vec3 load = Vec3::Zero();
    while (top > 0) {
        const Piece p = stack[--top];
        const Vec3 g = (p.corner_m[0] + p.corner_m[1] + p.corner_m[2]) / 3;
        double reach_m = 0;
        for (const Vec3& c : p.corner_m) reach_m = std::max(reach_m, (c - g).norm());
        const double distance_m = (g - centre_m).norm();
        if (distance_m - reach_m >= radius_m) continue;  // wholly outside the tip
        if (2 * reach_m <= leafSize_m || p.depth == kMaxSplits) {
            // The centroid rule on a piece under r/3 across; the piece's share goes to the face's corners
            // by the centroid's barycentric coordinates (the hat functions there).
            const double area_m2 = 0.5 * (p.corner_m[1] - p.corner_m[0]).cross(p.corner_m[2] - p.corner_m[0]).norm();
            load += tipPressure(distance_m / radius_m) * area_m2 * (p.bary[0] + p.bary[1] + p.bary[2]) / 3;
            continue;
        }
        const std::array<Vec3, 3> mid_m = {(p.corner_m[0] + p.corner_m[1]) / 2, (p.corner_m[1] + p.corner_m[2]) / 2,
                                           (p.corner_m[2] + p.corner_m[0]) / 2};
        const std::array<Vec3, 3> midBary = {(p.bary[0] + p.bary[1]) / 2, (p.bary[1] + p.bary[2]) / 2,
                                             (p.bary[2] + p.bary[0]) / 2};
        const int d = p.depth + 1;
        stack[top++] = Piece{{p.corner_m[0], mid_m[0], mid_m[2]}, {p.bary[0], midBary[0], midBary[2]}, d};
        stack[top++] = Piece{{mid_m[0], p.corner_m[1], mid_m[1]}, {midBary[0], p.bary[1], midBary[1]}, d};
        stack[top++] = Piece{{mid_m[2], mid_m[1], p.corner_m[2]}, {midBary[2], midBary[1], p.bary[2]}, d};
        stack[top++] = Piece{{mid_m[0], mid_m[1], mid_m[2]}, {midBary[0], midBary[1], midBary[2]}, d};
    }
    return load;
}

FootprintSpread ContactFootprint::spread(const collision::SurfaceView& s, const mesh::VertexFaces& around,
                                         std::span<const double> anchorStiffness_N_per_m, std::uint32_t face,
                                         const Vec3& bary, double radius_m, physics::PointSpring& tool) noexcept {
    begin(s, face, bary, radius_m);
    advance(s, around, kMaxQueuedFaces);
    return finish(s, around, anchorStiffness_N_per_m, tool);
}

void ContactFootprint::begin(const collision::SurfaceView& s, std::uint32_t face, const Vec3& bary,
                             double radius_m) noexcept {
    if (++stamp_ == 0) {  // the stamps wrapped: start them afresh
        std::fill(faceStamp_.begin(), faceStamp_.end(), 0);
        std::fill(nodeStamp_.begin(), nodeStamp_.end(), 0);
        stamp_ = 1;
    }
    face_ = face, bary_ = bary, radius_m_ = radius_m;
    centre_m_ = pointOnFace(s, face, bary);
    total_ = 0, next_ = 0, count_ = 0, complete_ = true;
    queue_.clear();
    queue_.push_back(face);
    faceStamp_[face] = stamp_;
}

bool ContactFootprint::advance(const collision::SurfaceView& s, const mesh::VertexFaces& around,
                               std::size_t maxFaces) noexcept {
    // The queue never holds more than kMaxQueuedFaces: so many faces finish any build.
    for (const std::size_t stop = next_ + std::min(maxFaces, kMaxQueuedFaces); next_ < queue_.size() && next_ < stop;
         ++next_) {
        const std::uint32_t f = queue_[next_];
        const Vec3 load = integrateFace(s, f, centre_m_, radius_m_);
        if (load == Vec3::Zero()) continue;  // beyond the tip: its neighbours are reached through nearer faces
        const mesh::Face& corners = s.faces[f];
        std::uint32_t fresh = 0;
        for (std::uint32_t v : corners) fresh += nodeStamp_[v] != stamp_;
        if (count_ + fresh > physics::kMaxContactNodes) {
            complete_ = false;
            continue;
        }
        const std::uint32_t firstNew = count_;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = corners[k];
            if (nodeStamp_[v] != stamp_) {
                nodeStamp_[v] = stamp_;
                nodeSlot_[v] = count_;
                nodes_[count_] = v;
                loads_[count_] = 0;
                ++count_;
            }
            loads_[nodeSlot_[v]] += load[k];
            total_ += load[k];
        }
        // The faces round each node newly under the tip, once per node: the footprint grows outwards.
        for (std::uint32_t k = firstNew; k < count_; ++k)
            for (std::uint32_t g : around.of(nodes_[k]))
                if (faceStamp_[g] != stamp_ && queue_.size() < kMaxQueuedFaces) {
                    faceStamp_[g] = stamp_;
                    queue_.push_back(g);
                }
    }
    return next_ == queue_.size();
}

FootprintSpread ContactFootprint::finish(const collision::SurfaceView& s, const mesh::VertexFaces& around,
                                         std::span<const double> anchorStiffness_N_per_m,
                                         physics::PointSpring& tool) noexcept {
    FootprintSpread result;
    result.complete = complete_;
    if (!(total_ > 0)) {  // nothing under the tip (a degenerate face): the thesis's point contact
        tool.touchTriangle(s.faces[face_], bary_);
        return result;
    }
    tool.count = count_;
    for (std::uint32_t k = 0; k < count_; ++k) {
        tool.nodes[k] = nodes_[k];
        tool.weights[k] = loads_[k] / total_;
    }
    tool.spread = true;
    tool.bary = bary_;
    result.subgridCompliance_m_per_N = subgridCompliance(s, around, anchorStiffness_N_per_m, total_);
    return result;
}

double ContactFootprint::subgridCompliance(const collision::SurfaceView& s, const mesh::VertexFaces& around,
                                           std::span<const double> anchorStiffness_N_per_m,
                                           double area_m2) const noexcept {
    // The anchors' stiffness per m² where the tip is: the touched triangle's corners' anchors over
    // their shares of the surface (a third of each face round them).
    const mesh::Face& corners = s.faces[face_];
    double anchors_N_per_m = 0, nodeArea_m2 = 0, resolved_m_per_N = 0;
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = corners[k];
        const double anchor = anchorStiffness_N_per_m[v];
        if (!(anchor > 0)) return 0;  // a node without an anchor: no foundation to model
        anchors_N_per_m += anchor;
        for (std::uint32_t g : around.of(v)) {
            const mesh::Face& f = s.faces[g];
            nodeArea_m2 +=
                (s.positions[f[1]] - s.positions[f[0]]).cross(s.positions[f[2]] - s.positions[f[0]]).norm() / 6;
        }
        // The dent the mesh shows at the tip's centre: its corners' own sinking, interpolated.
        if (nodeStamp_[v] == stamp_) resolved_m_per_N += bary_[k] * (loads_[nodeSlot_[v]] / area_m2) / anchor;
    }
    if (!(nodeArea_m2 > 0)) return 0;
    const double foundation_N_per_m3 = anchors_N_per_m / nodeArea_m2;
    return std::max(0.0, 1 / (foundation_N_per_m3 * area_m2) - resolved_m_per_N);
}

}  // namespace hapticut::haptics
