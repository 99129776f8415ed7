// Provot's strain limit.
#include "hapticut/physics/strain_limit.h"

namespace hapticut::physics {

long limitStrain(MassSpringModel& model, std::span<const std::uint32_t> springs, double maxStrain,
                 std::span<const std::uint8_t> movable, int passes) {
    Nodes& n = model.nodes;
    const Springs& s = model.springs;
    long corrections = 0;
    for (int pass = 0; pass < passes; ++pass) {
        long thisPass = 0;
        for (std::uint32_t k : springs) {
            const std::uint32_t a = s.a[k], b = s.b[k];
            const Vec3 d = n.position[b] - n.position[a];
            const double length = d.norm(), limit = (1 + maxStrain) * s.restLength[k];
            if (length <= limit || length < 1e-12) continue;
            const double wa = movable.empty() || movable[a] ? n.inverseMass[a] : 0.0;
            const double wb = movable.empty() || movable[b] ? n.inverseMass[b] : 0.0;
            if (!(wa + wb > 0)) continue;
            const Vec3 u = d / length;
            const double shareA = wa / (wa + wb), shareB = wb / (wa + wb);
            const double excess_m = length - limit;
            n.position[a] += shareA * excess_m * u;
            n.position[b] -= shareB * excess_m * u;
            const double parting_m_per_s = (n.velocity[b] - n.velocity[a]).dot(u);
            if (parting_m_per_s > 0) {
                n.velocity[a] += shareA * parting_m_per_s * u;
                n.velocity[b] -= shareB * parting_m_per_s * u;
            }
            ++thisPass;
        }
        corrections += thisPass;
        if (thisPass == 0) break;
    }
    return corrections;
}

}  // namespace hapticut::physics
