// Device workspace to scene: the automatic fit of a device's reach to the model, and the per-device
// mapping a user writes (scale, offset, rotation).
#pragma once

#include "hapticut/geometry/aabb.h"
#include "hapticut/haptics/device.h"

namespace hapticut::haptics {

/// The mapping that makes the device's box, turned by `rotation`, just cover the model's box grown by
/// `margin` (0.2: 20% on each side) and centred on it: one uniform scale, so shapes feel as they look.
/// The identity turned by `rotation` when either box is empty or flat.
WorkspaceTransform fitWorkspace(const geometry::Aabb& device_box, const geometry::Aabb& scene_box, double margin = 0.2,
                                const Eigen::Quaterniond& rotation = Eigen::Quaterniond::Identity());

}  // namespace hapticut::haptics
