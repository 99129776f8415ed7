// Workspace fitting.
#include "hapticut/haptics/workspace_fit.h"

#include <algorithm>

namespace hapticut::haptics {

WorkspaceTransform fitWorkspace(const geometry::Aabb& device_box, const geometry::Aabb& scene_box, double margin,
                                const Eigen::Quaterniond& rotation) {
    WorkspaceTransform w;
    w.rotation = rotation.normalized();
    if (device_box.empty() || scene_box.empty()) return w;
    // The device box's extent along the scene's axes once turned.
    const Vec3 turned = w.rotation.toRotationMatrix().cwiseAbs() * device_box.extent();
    const Vec3 wanted = scene_box.extent() * (1 + 2 * std::max(margin, 0.0));
    double scale = 0;
    for (int k = 0; k < 3; ++k)
        if (turned[k] > 0) scale = std::max(scale, wanted[k] / turned[k]);
    if (!(scale > 0)) return w;
    w.scale = scale;
    w.offset_m = scene_box.center() - w.rotation * (scale * device_box.center());
    return w;
}

}  // namespace hapticut::haptics
