// Force terms of the mass-spring model: structural springs, positioning springs, external forces.
#pragma once

#include <span>
#include <vector>

#include "hapticut/physics/mass_spring_model.h"
#include "hapticut/physics/node_springs.h"
#include "hapticut/physics/spring_kernels.h"

namespace hapticut::physics {

/// The springs' arrays as the SIMD kernels read them.
kernels::SpringArrays springArrays(const Springs& s);

/// The nodes' forces as the spring kernels sum them, a row a node; kept by the caller from step to step.
using ForceRows = std::vector<ForceRow>;

/// A coordinate of the external force less the positioning spring's (R4): zero rest length from the
/// node's rest position, f = -k (x - x0) - d v. The damping acts on the whole velocity, not only along
/// the spring: projected damping would leave motion around the anchor undamped and divide by a length
/// that is zero at rest.
inline double positioningForce(double external, double k, double d, double offset, double velocity) {
    return external - (k * offset + d * velocity);
}

/// A coordinate of a = F/m + g; a pinned node (no inverse mass) feels no gravity.
inline double acceleration(double inverseMass, double force, double gravity) {
    return inverseMass * force + (inverseMass > 0 ? gravity : 0.0);
}

/// f = positioningForce for nodes [0, count) at (x, v), three doubles a node; fourth doubles zero.
void startWithPositioningForces(const Nodes& n, std::size_t count, const double* x, const double* v, ForceRow* f);

/// Structural springs (R3): f_a = [k_s(|l| - r) + k_d (l'·l)/|l|] l/|l|, f_b = -f_a, with l = x_b - x_a.
void accumulateSpringForces(const Springs& s, std::span<const Vec3> x, std::span<const Vec3> v, std::span<ForceRow> f);

/// Accelerations a = F/m for state (x, v): springs, positioning springs (R4: zero rest length from each
/// node's rest position, damping the whole velocity), external forces and gravity. The forces are
/// summed in `forces`, which is sized here (it allocates only when the model has grown).
void computeAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                          std::span<Vec3> a, ForceRows& forces);
/// The same with forces summed in a buffer of its own, for a single evaluation.
void computeAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                          std::span<Vec3> a);

/// The same for an active region: accelerations of `nodes` from the springs listed in `springs`.
/// `touched` (nodes plus their resting neighbours) get the raw spring force instead, in newtons, so
/// the caller can tell which resting neighbours are being pulled awake.
void computeActiveAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                                std::span<Vec3> a, std::span<const std::uint32_t> nodes,
                                std::span<const std::uint32_t> touched, std::span<const std::uint32_t> springs,
                                ForceRows& forces);

/// The same as computeActiveAccelerations, for the listed nodes of `touched` only: awake nodes (by `awake`)
/// get their acceleration, resting ones the raw spring force in newtons, each summed over its own springs
/// (`springsAt`), where computeActiveAccelerations sums every spring of the region. The tools' reactions
/// are left out: the caller lists no node a tool loads.
void computeListedAccelerations(const MassSpringModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                                std::span<Vec3> a, std::span<const std::uint32_t> nodes,
                                std::span<const std::uint8_t> awake, const NodeSprings& springsAt);

}  // namespace hapticut::physics
