// The side of a closed surface from the faces round the nearest point.
#include "hapticut/collision/surface_side.h"

#include <algorithm>

#include "hapticut/geometry/triangle.h"

namespace hapticut::collision {

Side sideOfClosedSurface(const SurfaceView& s, const mesh::VertexFaces& topology, const SurfacePoint& nearest,
                         const Vec3& p) {
    const Vec3 away = p - nearest.point;
    const double distance = away.norm();
    if (distance == 0) return Side::Outside;
    // A face seen this close to edge-on cannot say: its normal's rounding would decide.
    const double confident = 1e-6 * distance;
    const mesh::Face& face = s.faces[nearest.face];
    auto sideOf = [&](std::uint32_t f) {
        const mesh::Face& g = s.faces[f];
        const double d = geometry::unitNormal(s.positions[g[0]], s.positions[g[1]], s.positions[g[2]]).dot(away);
        return d > confident ? 1 : d < -confident ? -1 : 0;
    };
    // The feature nearest.point lies on: the corners it does not weigh by zero (closestPointOnTriangle
    // gives exact zeros on edges and corners). One: a vertex; two: an edge; three: the face's inside.
    std::uint32_t feature[3];
    int corners = 0;
    for (int k = 0; k < 3; ++k)
        if (nearest.bary[k] != 0) feature[corners++] = face[static_cast<std::size_t>(k)];
    if (corners == 3 || corners == 0) {
        const int side = sideOf(nearest.face);
        return side > 0 ? Side::Outside : side < 0 ? Side::Inside : Side::Unsure;
    }
    // An edge: the faces holding both of its ends (two on a manifold). A vertex: every face round it.
    const std::uint32_t a = feature[0], b = corners == 2 ? feature[1] : feature[0];
    int agreed = 0, faces = 0;
    for (std::uint32_t f : topology.of(a)) {
        const mesh::Face& g = s.faces[f];
        if (b != a && std::find(g.begin(), g.end(), b) == g.end()) continue;
        const int side = sideOf(f);
        if (side == 0 || (agreed != 0 && side != agreed)) return Side::Unsure;
        agreed = side;
        ++faces;
    }
    if (faces == 0 || (corners == 2 && faces != 2)) return Side::Unsure;
    return agreed > 0 ? Side::Outside : Side::Inside;
}

}  // namespace hapticut::collision
