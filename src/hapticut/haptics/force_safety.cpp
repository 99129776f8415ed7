// Force limits.
#include "hapticut/haptics/force_safety.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hapticut::haptics {

Vec3 limitForceRate(const Vec3& previous, const Vec3& target, double maxChange_N) {
    if (target.squaredNorm() <= previous.squaredNorm() && target.dot(previous) >= 0) return target;
    const Vec3 change = target - previous;
    const double size = change.norm();
    if (size <= maxChange_N) return target;
    return previous + change * (std::max(maxChange_N, 0.0) / size);
}

double stiffnessCapAt(double nominal_N_per_m, double rate_hz) {
    // A device that states no rating (zero, negative or not a number) has no cap.
    if (!(nominal_N_per_m > 0) || std::isinf(nominal_N_per_m)) return std::numeric_limits<double>::infinity();
    return nominal_N_per_m * std::min(1.0, rate_hz / 1000);
}

}  // namespace hapticut::haptics
