// Provot's strain limit (Provot 1995, "Deformation constraints in a mass-spring model to describe
// rigid cloth behaviour"): after a step, springs stretched past a limit are pulled back to it.
#pragma once

#include <cstdint>
#include <span>

#include "hapticut/physics/mass_spring_model.h"

namespace hapticut::physics {

/// Gauss-Seidel passes over the springs per step: each fixes a spring at once, and a neighbour's fix
/// may stretch it again a little.
inline constexpr int kStrainLimitPasses = 10;

/// Brings every listed spring stretched past (1 + maxStrain) of its rest length back to that length,
/// moving its ends along it by their inverse masses, so the centre of mass stays put. Provot corrects
/// positions only; here the ends also lose the speed at which they were still parting, by an impulse
/// that keeps momentum and only takes energy out. A node whose `movable` flag is 0 (asleep at rest in
/// the active region) or whose mass is infinite stays where it is; an empty `movable` moves all.
/// Returns how many corrections were made.
long limitStrain(MassSpringModel& model, std::span<const std::uint32_t> springs, double maxStrain,
                 std::span<const std::uint8_t> movable, int passes = kStrainLimitPasses);

}  // namespace hapticut::physics
