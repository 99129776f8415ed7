// Polygonising an implicit surface by marching tetrahedra (Doi & Koide 1991), as a segmentation tool
// would: a closed surface with the thin triangles a voxel grid leaves, ready for repair and remeshing.
#pragma once

#include <functional>

#include "hapticut/geometry/aabb.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh::procedural {

/// A field that is negative inside the shape, positive outside and zero on its surface (m in, any unit out).
using ImplicitField = std::function<double(const Vec3&)>;

/// The zero set of `field` within `box`, sampled every `cell_m`: the grid's cubes are each split into six
/// tetrahedra along their main diagonal (the Kuhn split, which neighbouring cubes share face for face),
/// and each tetrahedron crossed by the surface gives one or two triangles. The grid's outer layer counts
/// as outside, so the result is closed; its faces are oriented outward. No UVs, normals or edges yet.
SurfaceMesh polygonise(const ImplicitField& field, const geometry::Aabb& box, double cell_m);

}  // namespace hapticut::mesh::procedural
