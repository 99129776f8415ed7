// A scene's [[regions]] as the material field the physics and the cutter read: tissue that is not
// uniform (a lump stiffer than the organ round it, a softer patch).
#pragma once

#include <filesystem>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/scene_file.h"

namespace hapticut::scene {

/// The scale at a point is that of the last region that holds it, else none. A mesh region's file is
/// loaded here (a closed surface, in metres, in the scene's coordinates); its errors name the scene's
/// file and the region's line. Empty (no field) for a scene without regions.
Result<physics::MaterialField, Error> materialField(const std::vector<SceneRegion>& regions,
                                                    const std::filesystem::path& sceneFile);

}  // namespace hapticut::scene
