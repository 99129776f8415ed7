// Isotropic remeshing to a target edge length (Botsch & Kobbelt 2004, "A remeshing approach to
// multiresolution modeling"): split long edges, collapse short ones, flip toward valence six, relax
// tangentially, project back onto the input surface. Boundaries and sharp features are kept. Then the
// thin and folded triangles that a noisy input leaves are mended by flips, collapses and smart Laplacian
// moves (Freitag, Jones and Plassmann 1995) judged against the input's normal smoothed over two edges.
// A rough input (a jittered segmentation, its faces folded against each other) is smoothed first
// (Taubin 1995), so that the passes can coarsen it.
#pragma once

#include <cstddef>
#include <string>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh {

struct RemeshOptions {
    double targetEdge_m = 0;  // the edge length aimed at (the first, with targetTriangles); > 0
    /// A triangle count to steer the edge length toward, pass by pass; 0 keeps targetEdge_m.
    std::size_t targetTriangles = 0;
    int iterations = 8;  // Botsch and Kobbelt use 5-10
    /// Edges whose faces meet at more than this dihedral angle (degrees) are features: they stay, and so
    /// do their vertices' places on them; 0 (the default) keeps none. Boundary edges always stay. Organs
    /// have no sharp edges, and a segmented or jittered surface bends sharply at every step of its noise:
    /// a 50 degree threshold locked 38,848 of a jittered heart's 75,114 edges.
    double featureAngle_deg = 0;
};

struct RemeshResult {
    SurfaceMesh mesh;
    long splits = 0, collapses = 0, flips = 0;
    long sliversMended = 0;        // thin triangles mended after the passes (an edit each)
    double targetEdge_m = 0;       // the edge length of the last pass
    std::size_t featureEdges = 0;  // of the input, kept
    double foldedInputShare = 0;   // the input's edges whose two faces face apart, as a share of its edges
    bool smoothedFirst = false;    // a rough input (many folded edges), smoothed before the passes
    /// How far the result lies from the input: the largest and mean distance of the result's vertices
    /// and face centres to the input surface (a sampled one-sided Hausdorff distance).
    double distanceMax_m = 0, distanceMean_m = 0;
};

/// The edge length at which an even triangulation of `mesh`'s area has about `triangles` faces.
double targetEdgeForTriangles(const SurfaceMesh& mesh, std::size_t triangles);

/// Remeshes a manifold mesh (repair it first: mesh/repair.h); an error for a non-manifold one or a
/// target that is not positive and finite. UVs are carried over from the input face nearest each new
/// face; normals and the edge list are recomputed.
Result<RemeshResult, std::string> remeshIsotropic(const SurfaceMesh& input, const RemeshOptions& options);

}  // namespace hapticut::mesh
