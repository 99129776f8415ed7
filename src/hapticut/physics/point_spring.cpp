// A tool pressing the surface, as a force term of the physics.
#include "hapticut/physics/point_spring.h"

namespace hapticut::physics {

Vec3 PointSpring::contactWeights(const Vec3& bary) {
    const Vec3 w = bary.cwiseMax(0.0).cwiseAbs2();
    return w.sum() > 0 ? Vec3(w / w.sum()) : Vec3::Constant(1.0 / 3);
}

Vec3 PointSpring::forceOnTool(std::span<const Vec3> x) const {
    const Vec3 p = bary.x() * x[nodes[0]] + bary.y() * x[nodes[1]] + bary.z() * x[nodes[2]];
    Vec3 f = stiffness_N_per_m * (p - anchor_m) - bias_N;
    if (f.dot(normal) < 0) return Vec3::Zero();
    const double len = f.norm();
    if (len > maxForce_N) f *= maxForce_N / len;
    return scale * f;
}

void PointSpring::addReaction(std::span<const Vec3> x, std::span<Vec3> f) const {
    if (!active) return;
    const Vec3 force = forceOnTool(x);
    for (int k = 0; k < 3; ++k) f[nodes[k]] -= weights[k] * force;
}

}  // namespace hapticut::physics
