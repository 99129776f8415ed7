// A tool pressing the surface, as a force term of the physics: a zero-rest-length spring from an
// anchor (the device) to a point on a triangle. Evaluated in every integrator stage, so stiff tool
// contact is integrated as stably as the tissue's own springs, not held fixed over a step.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>

#include "hapticut/geometry/vec.h"

namespace hapticut::physics {

/// Tools pressing one model at once: one per hand.
inline constexpr int kMaxTools = 2;

struct PointSpring {
    bool active = false;
    std::array<std::uint32_t, 3> nodes{};  // the touched triangle
    Vec3 bary = Vec3::Zero();              // where on it
    Vec3 weights = Vec3::Zero();           // share of the reaction per node (sums to 1)
    Vec3 anchor_m = Vec3::Zero();          // the device, shifted by the proxy's offset from the surface
    Vec3 bias_N = Vec3::Zero();            // constant part of the force (damping on the device velocity)
    double stiffness_N_per_m = 0;
    double maxForce_N = std::numeric_limits<double>::infinity();
    double scale = 1;            // ramp-in factor, applied after the clamp
    Vec3 normal = Vec3::Zero();  // outward contact normal: a tool pushes, never pulls (zero: no limit)

    /// The thesis's share of the reaction for each corner of the touched triangle (R9): the squared
    /// barycentric coordinate, normalised to sum to 1 (equal thirds if all are zero). Squaring makes the
    /// force shift smoothly from one face to the next as the contact slides over their common edge.
    static Vec3 contactWeights(const Vec3& bary);
    /// The force on the tool for node positions x: scale · clamp(k (p(x) - anchor) - bias), and zero
    /// when it would pull the tissue outward (the tissue has moved past the device: contact separates).
    Vec3 forceOnTool(std::span<const Vec3> x) const;
    /// Adds the reaction to the tissue's forces: -force spread over the triangle by the weights (R9).
    void addReaction(std::span<const Vec3> x, std::span<Vec3> f) const;
};

}  // namespace hapticut::physics
