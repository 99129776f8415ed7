// A tool pressing the surface, as a force term of the physics.
#include "hapticut/physics/point_spring.h"

#include <algorithm>

namespace hapticut::physics {

Vec3 PointSpring::contactWeights(const Vec3& bary) {
    const Vec3 w = bary.cwiseMax(0.0).cwiseAbs2();
    return w.sum() > 0 ? Vec3(w / w.sum()) : Vec3::Constant(1.0 / 3);
}

void PointSpring::touchTriangle(const std::array<std::uint32_t, 3>& face, const Vec3& at) {
    const Vec3 w = contactWeights(at);
    count = 3;
    for (int c = 0; c < 3; ++c) nodes[c] = face[c], weights[c] = w[c];
    spread = false;
    bary = at;
}

Vec3 PointSpring::heldPoint(std::span<const Vec3> x) const {
    if (!spread) return bary.x() * x[nodes[0]] + bary.y() * x[nodes[1]] + bary.z() * x[nodes[2]];
    Vec3 p = Vec3::Zero();
    for (std::uint32_t k = 0; k < count; ++k) p += weights[k] * x[nodes[k]];
    return p;
}

Vec3 PointSpring::forceAt(const Vec3& held_m) const {
    Vec3 f = stiffness_N_per_m * (held_m - anchor_m) - bias_N;
    if (f.dot(normal) < 0) return Vec3::Zero();
    const double len = f.norm();
    if (len > maxForce_N) f *= maxForce_N / len;
    return scale * f;
}

Vec3 PointSpring::forceOnTool(std::span<const Vec3> x) const { return forceAt(heldPoint(x)); }

namespace {

void subtract(Vec3& f, const Vec3& share) { f -= share; }
void subtract(ForceRow& f, const Vec3& share) { f.x -= share.x(), f.y -= share.y(), f.z -= share.z(); }

/// -force spread over the tool's loaded nodes by their weights, into forces of either layout.
template <class Force>
void spreadReaction(const PointSpring& tool, std::span<const Vec3> x, std::span<Force> f) {
    if (!tool.active) return;
    const Vec3 force = tool.forceOnTool(x);
    for (std::uint32_t k = 0; k < tool.count; ++k) subtract(f[tool.nodes[k]], tool.weights[k] * force);
}

}  // namespace

void PointSpring::addReaction(std::span<const Vec3> x, std::span<Vec3> f) const { spreadReaction(*this, x, f); }

void PointSpring::addReaction(std::span<const Vec3> x, std::span<ForceRow> f) const { spreadReaction(*this, x, f); }

void PointSpring::copyTo(PointSpring& other) const {
    other.active = active;
    other.count = count;
    std::copy_n(nodes.begin(), count, other.nodes.begin());
    std::copy_n(weights.begin(), count, other.weights.begin());
    other.spread = spread;
    other.bary = bary;
    other.anchor_m = anchor_m;
    other.bias_N = bias_N;
    other.stiffness_N_per_m = stiffness_N_per_m;
    other.maxForce_N = maxForce_N;
    other.scale = scale;
    other.normal = normal;
}

}  // namespace hapticut::physics
