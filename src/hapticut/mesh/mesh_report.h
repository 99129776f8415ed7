// Validation report of a mesh: counts, boundary, manifoldness, orientation, components, quality.
#pragma once

#include <optional>
#include <string>

#include <cstddef>

#include "hapticut/geometry/vec.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh {

struct MeshReport {
    std::size_t vertices = 0, faces = 0, edges = 0;
    std::size_t boundaryEdges = 0;     // edges with one face
    std::size_t nonManifoldEdges = 0;  // edges with three or more faces
    std::size_t misorientedEdges = 0;  // interior edges both faces traverse the same way
    std::size_t degenerateFaces = 0;   // zero area or repeated index
    std::size_t unusedVertices = 0;    // in no face
    std::size_t springs = 0;           // entries of the mesh's edge list
    std::size_t springsNotOnFaces = 0, faceEdgesWithoutSpring = 0;
    bool closed = false, manifold = false, oriented = false;
    std::size_t components = 0;    // face-connected pieces
    long eulerCharacteristic = 0;  // V - E + F over the used vertices
    Vec3 bboxMin = Vec3::Zero(), bboxMax = Vec3::Zero();
    double minAngleDeg = 0, meanEdgeLength_m = 0, shortestEdge_m = 0, area_m2 = 0;
};

MeshReport validateMesh(const SurfaceMesh& mesh);

/// For a mesh badly shaped for simulation and contact (a smallest angle under 5 degrees, or a shortest
/// edge under a twentieth of the mean: the slivers segmentation and decimation leave), what is wrong
/// and the remeshing that fixes it; nothing for a well-shaped one.
std::optional<std::string> shapeAdvice(const MeshReport& report);

}  // namespace hapticut::mesh
