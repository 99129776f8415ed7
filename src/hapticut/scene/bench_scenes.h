// What the benchmarks measure on, shared by bench/ and `hapticut bench`: the built-in heart at a
// given size and the device paths that keep a tool in contact with it.
#pragma once

#include "hapticut/geometry/vec.h"
#include "hapticut/mesh/surface_mesh.h"
#include "hapticut/scene/scene.h"

namespace hapticut::scene {

/// The built-in scene's heart with `triangles` triangles: its placed mesh and default material.
Scene benchHeart(int triangles);

/// The device at update `step` of a slide in contact: a 1 cm circle round (0, -1 cm), 5 mm under the
/// heart's front (z = 25 mm), 0.2 mm a step (0.2 m/s at 1 kHz), so that every proxy update collides,
/// slides and checks itself.
Vec3 slidingDevice_m(long step);

/// The heart's front-most vertex within 1 cm of (x, y) in the xy-plane: where a probe presses it.
Vec3 frontVertex_m(const mesh::SurfaceMesh& heart, double x_m, double y_m);

}  // namespace hapticut::scene
