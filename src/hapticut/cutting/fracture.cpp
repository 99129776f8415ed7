// The fracture rule for a blade held by a haptic coupling.
#include "hapticut/cutting/fracture.h"

namespace hapticut::cutting {

std::optional<Vec3> advancedCrackTip(const Vec3& blade_m, const Vec3& proxy_m, const Vec3& normal, double depth_m,
                                     double stiffness_N_per_m, const FractureParams& params) {
    if (!(stiffness_N_per_m > 0)) return std::nullopt;
    // The coupling's stretch along the surface: the proxy held back at the crack's end, the blade on.
    const Vec3 n = normal.normalized();
    const Vec3 stretch = blade_m - proxy_m;
    const Vec3 along = stretch - stretch.dot(n) * n;
    const double hold_m = cuttingForce_N(depth_m, params) / stiffness_N_per_m;
    const double length = along.norm();
    if (!(length > hold_m)) return std::nullopt;
    return blade_m - along * (hold_m / length);
}

std::optional<Vec3> advancedCrackTipAlongEdge(const Vec3& blade_m, const Vec3& tip_m, const Vec3& edge, double depth_m,
                                              double stiffness_N_per_m, const FractureParams& params) {
    if (!(stiffness_N_per_m > 0)) return std::nullopt;
    const double forward = (blade_m - tip_m).dot(edge);
    const double hold_m = cuttingForce_N(depth_m, params) / stiffness_N_per_m;
    if (!(forward > hold_m)) return std::nullopt;
    return tip_m + (forward - hold_m) * edge;
}

}  // namespace hapticut::cutting
