// Edge flips that raise the smallest angle of a triangle pair, for mesh quality without changing counts.
#pragma once

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh {

struct FlipOptions {
    int maxPasses = 20;
    /// Flip only across nearly flat edges (cosine of the angle between the two face normals), so that
    /// the shape is kept where the surface bends sharply.
    double minNormalCosine = 0.7;
};

/// Flips interior edges while that raises the pair's minimum angle. Faces stay consistently oriented;
/// mesh.edges and mesh.normals are recomputed. Per-corner UVs are recomputed by the caller if needed
/// (they are left as they were for the faces' new corners). Returns the number of flips.
int improveByEdgeFlips(SurfaceMesh& mesh, const FlipOptions& options = {});

}  // namespace hapticut::mesh
