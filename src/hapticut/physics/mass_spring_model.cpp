// Whole-model measures: mass, energies, momentum, displacement, finiteness.
#include "hapticut/physics/mass_spring_model.h"

#include <algorithm>

namespace hapticut::physics {

double totalMass(const MassSpringModel& model) {
    double m = 0;
    for (double mi : model.nodes.mass) m += mi;
    return m;
}

double kineticEnergy(const MassSpringModel& model) {
    double e = 0;
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
        e += 0.5 * model.nodes.mass[i] * model.nodes.velocity[i].squaredNorm();
    return e;
}

double potentialEnergy(const MassSpringModel& model) {
    const Nodes& n = model.nodes;
    const Springs& s = model.springs;
    double e = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const double stretch = (n.position[s.b[i]] - n.position[s.a[i]]).norm() - s.restLength[i];
        e += 0.5 * s.stiffness[i] * stretch * stretch;
    }
    for (std::size_t i = 0; i < n.size(); ++i)
        e += 0.5 * n.anchorStiffness[i] * (n.position[i] - n.restPosition[i]).squaredNorm();
    return e;
}

Vec3 linearMomentum(const MassSpringModel& model) {
    Vec3 p = Vec3::Zero();
    for (std::size_t i = 0; i < model.nodes.size(); ++i) p += model.nodes.mass[i] * model.nodes.velocity[i];
    return p;
}

double maxDisplacement(const MassSpringModel& model) {
    double d2 = 0;
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
        d2 = std::max(d2, (model.nodes.position[i] - model.nodes.restPosition[i]).squaredNorm());
    return std::sqrt(d2);
}

double maxDisplacement(const MassSpringModel& model, std::span<const std::uint32_t> nodes) {
    double d2 = 0;
    for (std::uint32_t i : nodes)
        d2 = std::max(d2, (model.nodes.position[i] - model.nodes.restPosition[i]).squaredNorm());
    return std::sqrt(d2);
}

bool allFinite(const MassSpringModel& model) {
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
        if (!model.nodes.position[i].allFinite() || !model.nodes.velocity[i].allFinite()) return false;
    return true;
}

double maxStrain(const MassSpringModel& model, std::size_t first, std::size_t last) {
    const Springs& s = model.springs;
    const std::vector<Vec3>& x = model.nodes.position;
    double worst = 0;
    for (std::size_t k = first; k < last; ++k)
        if (s.restLength[k] > 0)
            worst = std::max(worst, std::abs((x[s.b[k]] - x[s.a[k]]).norm() / s.restLength[k] - 1));
    return worst;
}

}  // namespace hapticut::physics
