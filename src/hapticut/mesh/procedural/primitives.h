// Closed primitive meshes (capped cylinder, sphere, convex prism) and mesh concatenation, for tools and tests.
#pragma once

#include <span>

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh::procedural {

/// Cylinder from `base` along `axis` (unit) of the given length, closed by flat caps.
SurfaceMesh makeCylinder(const Vec3& base, const Vec3& axis, double radius_m, double length_m, int segments);

/// UV sphere, closed (poles are single vertices).
SurfaceMesh makeSphere(const Vec3& centre, double radius_m, int segments, int rings);

/// Prism: a convex polygon in the xy plane (counter-clockwise), extruded from z0 to z1.
SurfaceMesh makePrism(std::span<const Vec2> polygon, double z0_m, double z1_m);

/// A flat square grid in the xy plane, n x n cells of `spacing_m`, centred at the origin, facing +z (open).
SurfaceMesh makeGrid(int n, double spacing_m);

/// Appends b to a (separate components), keeping every per-face array in step.
void appendMesh(SurfaceMesh& a, const SurfaceMesh& b);

}  // namespace hapticut::mesh::procedural
