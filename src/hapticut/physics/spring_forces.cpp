// Force terms of the mass-spring model.
#include "hapticut/physics/spring_forces.h"

#include "hapticut/physics/spring_kernels.h"

namespace hapticut::physics {

kernels::SpringArrays springArrays(const Springs& s) {
    return {s.a.data(), s.b.data(), s.restLength.data(), s.stiffness.data(), s.damping.data()};
}

void accumulateSpringForces(const Springs& s, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f) {
    kernels::addSpringForces(springArrays(s), s.size(), x.size(), coordinates(x.data()), coordinates(v.data()),
                             coordinates(f.data()));
}

namespace {

// Over plain arrays of coordinates, which vectorise; the sums are the Vec3 expressions' to the bit.

/// a = external force - positioning spring's force, for `count` nodes (R4): zero rest length from each
/// node's rest position, f = -k (x - x0) - d v. The damping acts on the whole velocity, not only along
/// the spring: projected damping would leave motion around the anchor undamped and divide by a length
/// that is zero at rest.
void startWithPositioningForces(const Nodes& n, std::size_t count, const double* __restrict x,
                                const double* __restrict v, double* __restrict a) {
    const double* __restrict rest = coordinates(n.restPosition.data());
    const double* __restrict external = coordinates(n.externalForce.data());
    const double* __restrict anchorStiffness = n.anchorStiffness.data();
    const double* __restrict anchorDamping = n.anchorDamping.data();
    for (std::size_t i = 0; i < count; ++i) {
        const double k = anchorStiffness[i], d = anchorDamping[i];
        for (std::size_t c = 3 * i; c < 3 * i + 3; ++c) a[c] = external[c] - (k * (x[c] - rest[c]) + d * v[c]);
    }
}

/// a = F/m + g, where a held the force F; a pinned node (no inverse mass) feels no gravity.
void forcesToAccelerations(const Nodes& n, const Vec3& gravity, std::size_t count, double* __restrict a) {
    const double* __restrict inverseMass = n.inverseMass.data();
    const double g[3] = {gravity.x(), gravity.y(), gravity.z()};
    for (std::size_t i = 0; i < count; ++i) {
        const double m = inverseMass[i];
        for (std::size_t c = 0; c < 3; ++c) a[3 * i + c] = m * a[3 * i + c] + (m > 0 ? g[c] : 0.0);
    }
}

}  // namespace

void computeAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                          std::span<Vec3> a) {
    if (a.empty()) return;
    startWithPositioningForces(model.nodes, a.size(), coordinates(x.data()), coordinates(v.data()),
                               coordinates(a.data()));
    accumulateSpringForces(model.springs, x, v, a);
    // The tissue feels each tool's force reversed, spread by the thesis's squared weights (R9).
    for (const PointSpring& tool : model.tools) tool.addReaction(x, a);
    forcesToAccelerations(model.nodes, model.gravity_m_per_s2, a.size(), coordinates(a.data()));
}

}  // namespace hapticut::physics

namespace hapticut::physics {

void computeActiveAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                                std::span<Vec3> a, std::span<const std::uint32_t> nodes,
                                std::span<const std::uint32_t> touched, std::span<const std::uint32_t> springs) {
    const Nodes& n = model.nodes;
    const Springs& s = model.springs;
    for (std::uint32_t i : touched) a[i] = Vec3::Zero();
    // Resting neighbours sit exactly at rest with zero velocity, so only the active nodes have
    // positioning, external and gravity forces.
    for (std::uint32_t i : nodes)
        a[i] = n.externalForce[i] - n.anchorStiffness[i] * (x[i] - n.restPosition[i]) - n.anchorDamping[i] * v[i];
    kernels::addListedSpringForces(springArrays(s), springs.data(), springs.size(), x.size(), coordinates(x.data()),
                                   coordinates(v.data()), coordinates(a.data()));
    for (const PointSpring& tool : model.tools) tool.addReaction(x, a);
    const Vec3 g = model.gravity_m_per_s2;
    for (std::uint32_t i : nodes) a[i] = n.inverseMass[i] * a[i] + (n.inverseMass[i] > 0 ? g : Vec3::Zero());
}

}  // namespace hapticut::physics
