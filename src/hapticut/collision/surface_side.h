// Which side of a closed surface a point is on, decided locally from its nearest surface point.
//
// Bærentzen & Aanæs 2005 ("Signed distance computation using the angle weighted pseudonormal"): on a
// closed, manifold triangle mesh the sign of (p - c) · n, with c the point of the surface nearest p and
// n the pseudonormal of the feature c lies on (a face's normal, the sum of an edge's two face normals,
// the angle-weighted normal of a vertex), says whether p is inside. That costs one nearest-point query
// near the surface, whatever the mesh's size, where ray parity crosses the whole organ.
#pragma once

#include "hapticut/collision/bvh.h"
#include "hapticut/mesh/vertex_faces.h"

namespace hapticut::collision {

enum class Side { Outside, Inside, Unsure };

/// The side of p given `nearest`, the surface's nearest point to p (its face and barycentric
/// coordinates, an edge or a vertex where they are zero). Every face round that feature must agree
/// for an answer, and then the pseudonormal, a sum of their normals with positive weights, agrees too.
/// Where they disagree (a sharp crease, a degenerate face, a feature seen at a grazing angle, a
/// non-manifold edge) it is Unsure, and a caller asks ray parity (point_inside.h): weighting slivers'
/// normals by their angles is what the theorem asks, but not what a mesh with needles can be trusted
/// with. A point on the surface is Outside.
Side sideOfClosedSurface(const SurfaceView& surface, const mesh::VertexFaces& topology, const SurfacePoint& nearest,
                         const Vec3& p);

}  // namespace hapticut::collision
