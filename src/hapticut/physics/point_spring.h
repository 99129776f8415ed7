// A tool pressing the surface, as a force term of the physics: a zero-rest-length spring from an
// anchor (the device) to the point of the surface the tool holds. Evaluated in every integrator stage,
// so stiff tool contact is integrated as stably as the tissue's own springs, not held fixed over a step.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>

#include "hapticut/geometry/vec.h"
#include "hapticut/physics/force_row.h"

namespace hapticut::physics {

/// Tools pressing one model at once: one per hand.
inline constexpr int kMaxTools = 2;

/// The most nodes one tool's load may spread over: a 7 mm tip on the heart at a million triangles
/// (0.2 mm edges) covers about 3,700.
inline constexpr std::uint32_t kMaxContactNodes = 4096;

struct PointSpring {
    bool active = false;
    /// The nodes that carry the tool's load and each one's share of it (the shares sum to 1). The
    /// thesis's contact (R9) is the touched triangle's three corners; a tip of finite size spreads
    /// over the nodes under its footprint (haptics/contact_footprint.h).
    std::uint32_t count = 0;
    std::array<std::uint32_t, kMaxContactNodes> nodes{};
    std::array<double, kMaxContactNodes> weights{};
    /// Where the spring holds the surface: with `spread`, the load-weighted mean of the nodes, so the
    /// force is the gradient of the spring's energy; without, the point `bary` on the triangle of the
    /// first three nodes, as in the thesis.
    bool spread = false;
    Vec3 bary = Vec3::Zero();
    Vec3 anchor_m = Vec3::Zero();  // the device, shifted by the proxy's offset from the surface
    Vec3 bias_N = Vec3::Zero();    // constant part of the force (damping on the device velocity)
    double stiffness_N_per_m = 0;
    double maxForce_N = std::numeric_limits<double>::infinity();
    double scale = 1;            // ramp-in factor, applied after the clamp
    Vec3 normal = Vec3::Zero();  // the way the tool pushes; it never pulls against it (zero: no limit)

    /// The thesis's share of the reaction for each corner of the touched triangle (R9): the squared
    /// barycentric coordinate, normalised to sum to 1 (equal thirds if all are zero). Squaring makes the
    /// force shift smoothly from one face to the next as the contact slides over their common edge.
    static Vec3 contactWeights(const Vec3& bary);
    /// The thesis's contact: the point `bary` on `face`, its load shared by contactWeights.
    void touchTriangle(const std::array<std::uint32_t, 3>& face, const Vec3& bary);
    std::span<const std::uint32_t> loadedNodes() const { return {nodes.data(), count}; }
    /// The point of the surface the spring holds, for node positions x.
    Vec3 heldPoint(std::span<const Vec3> x) const;
    /// The force on the tool for node positions x: scale · clamp(k (p(x) - anchor) - bias), and zero
    /// when it would pull the tissue outward (the tissue has moved past the device: contact separates).
    Vec3 forceOnTool(std::span<const Vec3> x) const;
    /// forceOnTool with the held point given.
    Vec3 forceAt(const Vec3& held_m) const;
    /// Adds the reaction to the tissue's forces: -force spread over the loaded nodes by their weights.
    void addReaction(std::span<const Vec3> x, std::span<Vec3> f) const;
    /// The same on force rows (the explicit integrators'), to the same bits.
    void addReaction(std::span<const Vec3> x, std::span<ForceRow> f) const;
    /// Copies what is in use (the loaded nodes' prefix of the arrays), for handing the tool on each step.
    void copyTo(PointSpring& other) const;
};

}  // namespace hapticut::physics
