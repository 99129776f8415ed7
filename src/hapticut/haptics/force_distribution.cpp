// The reaction force on the tissue and the force on the device.
#include "hapticut/haptics/force_distribution.h"

namespace hapticut::haptics {

void distributeToTriangle(const Vec3& force_N, const mesh::Face& face, const Vec3& bary, std::span<Vec3> node_forces) {
    const Vec3 w = bary.cwiseMax(0.0).cwiseAbs2();
    const double sum = w.sum();
    const Vec3 weights = sum > 0 ? Vec3(w / sum) : Vec3::Constant(1.0 / 3);
    for (int k = 0; k < 3; ++k) node_forces[face[k]] += weights[k] * force_N;
}

Vec3 clampLength(const Vec3& v, double max_length) {
    const double len = v.norm();
    return len > max_length ? Vec3(v * (max_length / len)) : v;
}

Vec3 couplingForce(const Vec3& proxy_m, const Vec3& device_m, const Vec3& device_velocity_m_per_s, double stiffness_N_per_m,
                   double damping_Ns_per_m, double max_force_N) {
    return clampLength(stiffness_N_per_m * (proxy_m - device_m) - damping_Ns_per_m * device_velocity_m_per_s, max_force_N);
}

}  // namespace hapticut::haptics
