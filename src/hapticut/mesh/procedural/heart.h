// Procedural heart: a closed, well-shaped triangle mesh of a requested size, with UVs.
#pragma once

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh::procedural {

struct HeartOptions {
    int triangles = 1619;    // the result is within 2% of this (a closed surface has an even count)
    double length_m = 0.12;  // extent along the long axis (y, apex toward -y)
    int smoothingIterations = 12;
};

/// A heart centred at the origin (bounding box centre), long axis +y, front facing +z:
/// two ventricles, two atria and the aorta and pulmonary trunk blended into one smooth closed surface.
SurfaceMesh makeHeart(const HeartOptions& options = {});

/// Distance from the heart's centre to its surface along `direction` (unit), in the generator's units.
double heartRadius(const Vec3& direction);

}  // namespace hapticut::mesh::procedural
