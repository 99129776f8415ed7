// Vector types used across Hapticut (Eigen fixed-size, double precision, SI units).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace hapticut {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

}  // namespace hapticut
