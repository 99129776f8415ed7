// Is a point inside a closed surface? Ray parity, independent of how the proxy found its position.
#pragma once

#include "hapticut/collision/bvh.h"

namespace hapticut::collision {

/// Casts three rays in fixed, unrelated directions and takes the majority of their crossing parities,
/// so one ray grazing an edge cannot flip the answer. Meaningful for closed surfaces only.
bool insideClosedSurface(const Bvh& bvh, const SurfaceView& surface, const Vec3& p);

/// How deep p is inside a closed surface (m): its distance to the surface when inside, else 0.
double penetrationDepth(const Bvh& bvh, const SurfaceView& surface, const Vec3& p);

}  // namespace hapticut::collision
