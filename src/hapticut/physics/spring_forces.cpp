// Force terms of the mass-spring model.
#include "hapticut/physics/spring_forces.h"

namespace hapticut::physics {

void accumulateSpringForces(const Springs& s, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f) {
    const std::size_t count = s.size();
    const std::uint32_t* a = s.a.data();
    const std::uint32_t* b = s.b.data();
    for (std::size_t i = 0; i < count; ++i) {
        const Vec3 d = x[b[i]] - x[a[i]];
        const double len2 = d.squaredNorm();
        if (len2 < 1e-24) continue;  // coincident nodes have no direction; a fresh cut can produce them
        const double invLen = 1 / std::sqrt(len2);
        const double stretchRate = (v[b[i]] - v[a[i]]).dot(d) * invLen;  // m/s
        const double magnitude = s.stiffness[i] * (len2 * invLen - s.restLength[i]) + s.damping[i] * stretchRate;
        const Vec3 fa = (magnitude * invLen) * d;
        f[a[i]] += fa;
        f[b[i]] -= fa;
    }
}

void accumulatePositioningForces(const Nodes& n, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f) {
    for (std::size_t i = 0; i < x.size(); ++i) f[i] -= n.anchorStiffness[i] * (x[i] - n.restPosition[i]) + n.anchorDamping[i] * v[i];
}

void computeAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> a) {
    const Nodes& n = model.nodes;
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = n.externalForce[i];
    accumulatePositioningForces(n, x, v, a);
    accumulateSpringForces(model.springs, x, v, a);
    const Vec3 g = model.gravity_m_per_s2;
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = n.inverseMass[i] * a[i] + (n.inverseMass[i] > 0 ? g : Vec3::Zero());
}

}  // namespace hapticut::physics
