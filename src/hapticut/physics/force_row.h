// A node's force as the explicit integrators sum it: a row of four doubles, one vector wide.
#pragma once

namespace hapticut::physics {

/// x, y, z and a fourth double that stays as it was given (zero), 32 bytes aligned, so that a spring
/// adds to each of its ends with one vector load, addition and store where three doubles a node would
/// take two of each (spring_kernels.h).
struct alignas(32) ForceRow {
    double x = 0, y = 0, z = 0, unused = 0;
};

}  // namespace hapticut::physics
