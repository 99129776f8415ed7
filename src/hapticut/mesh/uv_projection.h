// Spherical texture coordinates about a centre, with the seam handled per corner.
#pragma once

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh {

/// u around the y axis (0.5 toward +z), v from -y (0) to +y (1), seen from `centre`. A face across the
/// seam gets u + 1 on its low side; at a pole, where u is undefined, a corner takes the mean u of the
/// face's other corners.
void sphericalUvs(SurfaceMesh& mesh, const Vec3& centre);

}  // namespace hapticut::mesh
