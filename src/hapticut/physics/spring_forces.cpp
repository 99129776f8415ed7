// Force terms of the mass-spring model.
#include "hapticut/physics/spring_forces.h"

#include "hapticut/physics/spring_kernels.h"

namespace hapticut::physics {

kernels::SpringArrays springArrays(const Springs& s) {
    return {s.a.data(), s.b.data(), s.restLength.data(), s.stiffness.data(), s.damping.data()};
}

void accumulateSpringForces(const Springs& s, std::span<const Vec3> x, std::span<const Vec3> v, std::span<ForceRow> f) {
    kernels::addSpringForces(springArrays(s), s.size(), coordinates(x.data()), coordinates(v.data()), f.data());
}

void startWithPositioningForces(const Nodes& n, std::size_t count, const double* __restrict x,
                                const double* __restrict v, ForceRow* __restrict f) {
    const double* __restrict rest = coordinates(n.restPosition.data());
    const double* __restrict external = coordinates(n.externalForce.data());
    const double* __restrict anchorStiffness = n.anchorStiffness.data();
    const double* __restrict anchorDamping = n.anchorDamping.data();
    for (std::size_t i = 0; i < count; ++i) {
        const double k = anchorStiffness[i], d = anchorDamping[i];
        double row[4] = {0, 0, 0, 0};
        for (std::size_t c = 0; c < 3; ++c) {
            const std::size_t j = 3 * i + c;
            row[c] = positioningForce(external[j], k, d, x[j] - rest[j], v[j]);
        }
        f[i] = {row[0], row[1], row[2], row[3]};
    }
}

namespace {

// Over plain arrays; the sums are the Vec3 expressions' to the bit.

/// a = F/m + g (acceleration), where f holds the force F.
void forcesToAccelerations(const Nodes& n, const Vec3& gravity, std::size_t count, const ForceRow* __restrict f,
                           double* __restrict a) {
    const double* __restrict inverseMass = n.inverseMass.data();
    const double g[3] = {gravity.x(), gravity.y(), gravity.z()};
    for (std::size_t i = 0; i < count; ++i) {
        const double m = inverseMass[i];
        const double force[3] = {f[i].x, f[i].y, f[i].z};
        for (std::size_t c = 0; c < 3; ++c) a[3 * i + c] = acceleration(m, force[c], g[c]);
    }
}

}  // namespace

void computeAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                          std::span<Vec3> a, ForceRows& forces) {
    if (a.empty()) return;
    if (forces.size() < a.size()) forces.resize(a.size());
    const std::span<ForceRow> f(forces.data(), a.size());
    startWithPositioningForces(model.nodes, a.size(), coordinates(x.data()), coordinates(v.data()), f.data());
    accumulateSpringForces(model.springs, x, v, f);
    // The tissue feels each tool's force reversed, spread by the thesis's squared weights (R9).
    for (const PointSpring& tool : model.tools) tool.addReaction(x, f);
    forcesToAccelerations(model.nodes, model.gravity_m_per_s2, a.size(), f.data(), coordinates(a.data()));
}

void computeListedAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                                std::span<Vec3> a, std::span<const std::uint32_t> nodes,
                                std::span<const std::uint8_t> awake, const NodeSprings& springsAt) {
    const Nodes& n = model.nodes;
    const kernels::SpringArrays springs = springArrays(model.springs);
    const Vec3 g = model.gravity_m_per_s2;
    for (const std::uint32_t i : nodes) {
        // As computeActiveAccelerations: only awake nodes have positioning, external and gravity forces.
        Vec3 f = awake[i] ? Vec3(n.externalForce[i] - n.anchorStiffness[i] * (x[i] - n.restPosition[i]) -
                                 n.anchorDamping[i] * v[i])
                          : Vec3::Zero();
        const std::span<const std::uint32_t> at = springsAt.of(i);
        kernels::addSpringForcesOn(springs, i, at.data(), at.size(), coordinates(x.data()), coordinates(v.data()),
                                   f.data());
        a[i] = awake[i] ? Vec3(n.inverseMass[i] * f + (n.inverseMass[i] > 0 ? g : Vec3::Zero())) : f;
    }
}

void computeAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                          std::span<Vec3> a) {
    ForceRows forces;
    computeAccelerations(model, x, v, a, forces);
}

void computeActiveAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                                std::span<Vec3> a, std::span<const std::uint32_t> nodes,
                                std::span<const std::uint32_t> touched, std::span<const std::uint32_t> springs,
                                ForceRows& forces) {
    const Nodes& n = model.nodes;
    const Springs& s = model.springs;
    if (forces.size() < a.size()) forces.resize(a.size());
    const std::span<ForceRow> f(forces.data(), a.size());
    for (std::uint32_t i : touched) f[i] = {};
    // Resting neighbours sit exactly at rest with zero velocity, so only the active nodes have
    // positioning, external and gravity forces.
    for (std::uint32_t i : nodes) {
        const Vec3 start =
            n.externalForce[i] - n.anchorStiffness[i] * (x[i] - n.restPosition[i]) - n.anchorDamping[i] * v[i];
        f[i] = {start.x(), start.y(), start.z(), 0};
    }
    kernels::addListedSpringForces(springArrays(s), springs.data(), springs.size(), coordinates(x.data()),
                                   coordinates(v.data()), f.data());
    for (const PointSpring& tool : model.tools) tool.addReaction(x, f);
    for (std::uint32_t i : touched) a[i] = Vec3(f[i].x, f[i].y, f[i].z);
    const Vec3 g = model.gravity_m_per_s2;
    for (std::uint32_t i : nodes)
        a[i] = n.inverseMass[i] * Vec3(f[i].x, f[i].y, f[i].z) + (n.inverseMass[i] > 0 ? g : Vec3::Zero());
}

}  // namespace hapticut::physics
