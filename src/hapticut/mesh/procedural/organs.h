// Procedural liver and kidney, each with a neighbour as a second named part: segmented from implicit
// shapes the way a user's CT organs are, then made simulation-ready by repair and isotropic remeshing.
#pragma once

#include <cstddef>
#include <string>

#include "hapticut/common/result.h"
#include "hapticut/mesh/remesh.h"
#include "hapticut/mesh/repair.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh::procedural {

/// A liver (a domed right lobe, a thinner left lobe, the flattened visceral surface, the notch of the
/// round ligament) and the gallbladder in its fossa beneath, 4 mm apart: parts "liver" and "gallbladder".
/// About 24 cm across, centred at the origin, up +y, front +z, the patient's right toward -x.
/// Polygonised on a grid of `cell_m`, so it has a segmentation's thin triangles.
SurfaceMesh segmentLiver(double cell_m = 0.004);

/// A kidney (bean-shaped, 11 cm long, the hilum on its medial side, +x) and the adrenal gland capping
/// it 4 mm above: parts "kidney" and "adrenal gland". Centred at the origin, up +y, front +z.
SurfaceMesh segmentKidney(double cell_m = 0.003);

struct ReadyOrgan {
    SurfaceMesh mesh;
    RepairReport repair;
    RemeshResult remesh;  // its mesh moved into `mesh`
};

/// What `convert --repair --remesh TRIANGLES` does: every part cleaned, oriented outward and remeshed
/// to about `triangles` faces in all, evenly sized across the parts.
Result<ReadyOrgan, std::string> makeSimulationReady(SurfaceMesh segmented, std::size_t triangles);

}  // namespace hapticut::mesh::procedural
