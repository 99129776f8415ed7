// Vector types used across Hapticut (Eigen fixed-size, double precision, SI units).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace hapticut {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// A Vec3 is three doubles in a row, so an array of them is an array of 3 n doubles: what SIMD kernels and
// loops the compiler vectorises read.
static_assert(sizeof(Vec3) == 3 * sizeof(double));
inline const double* coordinates(const Vec3* p) { return reinterpret_cast<const double*>(p); }
inline double* coordinates(Vec3* p) { return reinterpret_cast<double*>(p); }

}  // namespace hapticut
