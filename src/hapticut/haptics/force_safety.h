// The limits every force passes before it reaches a hand: how fast it may grow, how stiff a device may
// be asked to be at the loop's rate.
#pragma once

#include "hapticut/geometry/vec.h"

namespace hapticut::haptics {

/// The force to send after `previous` when the loop wants `target`. Easing off is sent at once: a
/// force that shrinks without turning (target within 90 degrees of previous, or zero) is never the
/// danger. Anything else moves toward `target` by at most `maxChange_N`, so a sudden contact or a
/// reversal reaches the hand as a ramp instead of a jolt.
Vec3 limitForceRate(const Vec3& previous, const Vec3& target, double maxChange_N);

/// The coupling stiffness a device rated `nominal_N_per_m` at a 1 kHz servo renders stably at `rate_hz`:
/// the rating itself at 1 kHz or faster, proportionally less when slower (a spring's stability limit
/// grows with the sample rate). Infinite for a device with no rating.
double stiffnessCapAt(double nominal_N_per_m, double rate_hz);

}  // namespace hapticut::haptics
