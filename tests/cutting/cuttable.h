// A cuttable organ made from a mesh with the default material, shared by the cutting tests.
#pragma once

#include "hapticut/cutting/cut_model.h"
#include "hapticut/physics/material.h"

namespace hapticut::cutting::test {

inline CutModel cuttable(const mesh::SurfaceMesh& mesh) {
    return CutModel(mesh, physics::buildModel(mesh, physics::Material{}));
}

}  // namespace hapticut::cutting::test
