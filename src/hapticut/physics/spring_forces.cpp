// Force terms of the mass-spring model.
#include "hapticut/physics/spring_forces.h"

#include <cmath>

namespace hapticut::physics {

void accumulateSpringForces(const Springs& s, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f) {
    // Raw restrict pointers: without them the compiler must assume that every store into f may change
    // the springs' arrays, and reloads each array's base pointer on every iteration.
    const std::size_t count = s.size();
    const std::uint32_t* __restrict a = s.a.data();
    const std::uint32_t* __restrict b = s.b.data();
    const double* __restrict rest = s.restLength.data();
    const double* __restrict ks = s.stiffness.data();
    const double* __restrict kd = s.damping.data();
    const double* __restrict xp = x.data()->data();
    const double* __restrict vp = v.data()->data();
    double* __restrict fp = f.data()->data();
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t ia = 3 * std::size_t{a[i]}, ib = 3 * std::size_t{b[i]};
        const double dx = xp[ib] - xp[ia], dy = xp[ib + 1] - xp[ia + 1], dz = xp[ib + 2] - xp[ia + 2];
        const double len2 = dx * dx + dy * dy + dz * dz;
        if (len2 < 1e-24) continue;  // coincident nodes have no direction; a fresh cut can produce them
        const double invLen = 1 / std::sqrt(len2);
        const double dvx = vp[ib] - vp[ia], dvy = vp[ib + 1] - vp[ia + 1], dvz = vp[ib + 2] - vp[ia + 2];
        const double stretchRate = (dvx * dx + dvy * dy + dvz * dz) * invLen;  // m/s
        const double scale = (ks[i] * (len2 * invLen - rest[i]) + kd[i] * stretchRate) * invLen;
        const double fx = scale * dx, fy = scale * dy, fz = scale * dz;
        fp[ia] += fx, fp[ia + 1] += fy, fp[ia + 2] += fz;
        fp[ib] -= fx, fp[ib + 1] -= fy, fp[ib + 2] -= fz;
    }
}

void accumulatePositioningForces(const Nodes& n, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f) {
    for (std::size_t i = 0; i < x.size(); ++i)
        f[i] -= n.anchorStiffness[i] * (x[i] - n.restPosition[i]) + n.anchorDamping[i] * v[i];
}

void computeAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                          std::span<Vec3> a) {
    const Nodes& n = model.nodes;
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = n.externalForce[i];
    accumulatePositioningForces(n, x, v, a);
    accumulateSpringForces(model.springs, x, v, a);
    // The tissue feels each tool's force reversed, spread by the thesis's squared weights (R9).
    for (const PointSpring& tool : model.tools) tool.addReaction(x, a);
    const Vec3 g = model.gravity_m_per_s2;
    for (std::size_t i = 0; i < a.size(); ++i)
        a[i] = n.inverseMass[i] * a[i] + (n.inverseMass[i] > 0 ? g : Vec3::Zero());
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
    for (std::uint32_t k : springs) {
        const std::uint32_t ia = s.a[k], ib = s.b[k];
        const Vec3 d = x[ib] - x[ia];
        const double len2 = d.squaredNorm();
        if (len2 < 1e-24) continue;
        const double invLen = 1 / std::sqrt(len2);
        const double stretchRate = (v[ib] - v[ia]).dot(d) * invLen;
        const Vec3 fa =
            ((s.stiffness[k] * (len2 * invLen - s.restLength[k]) + s.damping[k] * stretchRate) * invLen) * d;
        a[ia] += fa;
        a[ib] -= fa;
    }
    for (const PointSpring& tool : model.tools) tool.addReaction(x, a);
    const Vec3 g = model.gravity_m_per_s2;
    for (std::uint32_t i : nodes) a[i] = n.inverseMass[i] * a[i] + (n.inverseMass[i] > 0 ? g : Vec3::Zero());
}

}  // namespace hapticut::physics
