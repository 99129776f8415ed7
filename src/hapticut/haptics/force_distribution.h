// The reaction force on the tissue (SPEC R9) and the force on the device (DESIGN, the loop, step 3).
#pragma once

#include <cstdint>
#include <span>

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::haptics {

/// Spreads `force_N` over the corners of a face. The thesis weights corner a by x², where
/// x = |bc x kb| / |bc x ab| is the barycentric coordinate of the contact point k; squaring makes the
/// force shift smoothly between faces. The weights are normalised, so the added forces sum exactly
/// to force_N. Adds into `node_forces`.
void distributeToTriangle(const Vec3& force_N, const mesh::Face& face, const Vec3& bary, std::span<Vec3> node_forces);

/// Device force F = k (proxy - device) - b v_device, clamped in length to max_force_N.
Vec3 couplingForce(const Vec3& proxy_m, const Vec3& device_m, const Vec3& device_velocity_m_per_s, double stiffness_N_per_m,
                   double damping_Ns_per_m, double max_force_N);

/// Scales v down to at most `max_length` (unchanged if shorter).
Vec3 clampLength(const Vec3& v, double max_length);

}  // namespace hapticut::haptics
