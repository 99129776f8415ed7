// Cleaning and repairing imported meshes: weld, drop degenerate and duplicate faces, orient, split
// non-manifold edges, remove fragments, generate UVs, fit the unit box.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh {

struct RepairOptions {
    /// Vertices closer than this are one (m). Negative: 1e-9 of the bounding-box diagonal, which joins
    /// exact duplicates (STL's per-corner vertices) and nothing else.
    double weldEpsilon_m = -1;
    /// Also fix what can be fixed safely: orientation, non-manifold edges and vertices, small fragments.
    bool repair = false;
    /// With repair: pieces with fewer than this share of the faces go (the largest piece always stays).
    double minComponentShare = 0.01;
};

struct RepairReport {
    std::size_t weldedVertices = 0, degenerateFaces = 0, duplicateFaces = 0, unusedVertices = 0;
    std::size_t separatedVertices = 0;  // copies made to part pieces that touched at an edge or a vertex
    std::size_t flippedFaces = 0, splitNonManifoldEdges = 0, splitNonManifoldVertices = 0, removedComponents = 0,
                removedComponentFaces = 0;
    bool generatedUvs = false;
    std::vector<std::string> notes;  // one line per thing done, for the user
};

/// Always welds, drops degenerate and duplicate faces and unused vertices, and generates spherical UVs
/// when the mesh has none; with options.repair also orients, splits non-manifold edges and removes
/// small components. Recomputes normals and the edge list.
RepairReport cleanMesh(SurfaceMesh& mesh, const RepairOptions& options = {});

/// The closed pieces of a mesh that were turned outward.
struct TurnedOutward {
    std::size_t pieces = 0, faces = 0;
    std::vector<std::string> parts;  // the named parts they belong to, each once
};

/// Turns outward each closed, consistently oriented piece whose faces all face inward (a negative
/// enclosed volume), as files exported inside out come: contact, the tissue's volume and shading all take
/// a face's normal to point out of the tissue. Pieces that are open or disagree within themselves are
/// left to cleanMesh's repair. Cheap enough to run on every load: one pass over the edges.
TurnedOutward turnInsideOutPiecesOutward(SurfaceMesh& mesh);

/// Scales and moves the mesh into the unit box centred at the origin (largest extent 1), as the
/// thesis's models had to be.
void fitUnitBox(SurfaceMesh& mesh);

}  // namespace hapticut::mesh
