// Assembly and products of the backward-Euler system.
#include "hapticut/physics/backward_euler_system.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "hapticut/common/reserve.h"

namespace hapticut::physics {

void BackwardEulerSystem::reserve(std::size_t nodes, std::size_t springs) {
    reserveTouched(nodeDiagonal_, nodes);
    reserveTouched(inverseBlock_, nodes);
    reserveTouched(rhs_, nodes);
    reserveTouched(pinned_, nodes);
    reserveTouched(springScalar_, springs);
    reserveTouched(springAxis_, springs);
}

void BackwardEulerSystem::resize(std::size_t nodes, std::size_t springs) {
    nodeDiagonal_.resize(std::max(nodes, nodeDiagonal_.size()), 0.0);
    inverseBlock_.resize(std::max(nodes, inverseBlock_.size()), Mat3::Zero());
    rhs_.resize(std::max(nodes, rhs_.size()), Vec3::Zero());
    springScalar_.resize(std::max(springs, springScalar_.size()), 0.0);
    springAxis_.resize(std::max(springs, springAxis_.size()), Vec3::Zero());
}

void BackwardEulerSystem::assemble(const MassSpringModel& model, double h, SolveRegion region) {
    region_ = region;
    springs_ = &model.springs;
    const Nodes& n = model.nodes;
    const Springs& s = model.springs;
    const std::vector<Vec3>& x = n.position;
    const std::vector<Vec3>& v = n.velocity;
    const double h2 = h * h;
    // inverseBlock_ holds the diagonal blocks' spring parts until they are inverted below.
    for (std::uint32_t i : region.touched) {
        nodeDiagonal_[i] = 0;
        inverseBlock_[i].setZero();
        rhs_[i].setZero();
    }
    const Vec3 g = model.gravity_m_per_s2;
    for (std::uint32_t i : region.nodes) {
        const double k = n.anchorStiffness[i], d = n.anchorDamping[i];
        const Vec3 f = n.externalForce[i] - k * (x[i] - n.restPosition[i]) - d * v[i] +
                       (n.inverseMass[i] > 0 ? Vec3(n.mass[i] * g) : Vec3::Zero());
        rhs_[i] = h * f - h2 * k * v[i];
        nodeDiagonal_[i] = n.mass[i] + h * d + h2 * k;
    }
    for (const PointSpring& tool : model.tools) {
        if (!tool.active) continue;
        const Vec3 force = tool.forceOnTool(x);
        // A clamped force no longer grows with the press: its stiffness is left out of the matrix.
        const Vec3 p = tool.bary.x() * x[tool.nodes[0]] + tool.bary.y() * x[tool.nodes[1]] +
                       tool.bary.z() * x[tool.nodes[2]];
        const bool linear = force != Vec3::Zero() &&
                            (tool.stiffness_N_per_m * (p - tool.anchor_m) - tool.bias_N).norm() <= tool.maxForce_N;
        const double k = linear ? tool.scale * tool.stiffness_N_per_m : 0.0;
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t i = tool.nodes[c];
            const double w = tool.weights[c];
            rhs_[i] -= h * w * force + h2 * k * w * v[i];
            nodeDiagonal_[i] += h2 * k * w;
        }
    }
    for (std::uint32_t e : region.springs) {
        const std::uint32_t a = s.a[e], b = s.b[e];
        const Vec3 d = x[b] - x[a];
        const double len2 = d.squaredNorm();
        if (len2 < 1e-24) {  // coincident ends have no direction, as in the explicit force
            springScalar_[e] = 0;
            springAxis_[e].setZero();
            continue;
        }
        const double len = std::sqrt(len2);
        const Vec3 dir = d / len;
        const Vec3 dv = v[b] - v[a];
        const double k = s.stiffness[e], kd = s.damping[e];
        const Vec3 force = (k * (len - s.restLength[e]) + kd * dv.dot(dir)) * dir;  // on a
        const double alpha = std::max(0.0, 1 - s.restLength[e] / len);
        const Vec3 stiffnessTimesDv = k * (alpha * dv + (1 - alpha) * dir.dot(dv) * dir);
        const Vec3 contribution = h * force + h2 * stiffnessTimesDv;
        rhs_[a] += contribution;
        rhs_[b] -= contribution;
        const double c0 = h2 * k * alpha, c1 = h2 * k * (1 - alpha) + h * kd;
        const Vec3 u = std::sqrt(c1) * dir;
        springScalar_[e] = c0;
        springAxis_[e] = u;
        const Mat3 block = c0 * Mat3::Identity() + u * u.transpose();
        inverseBlock_[a] += block;
        inverseBlock_[b] += block;
    }
    pinned_.clear();
    for (std::uint32_t i : region.nodes) {
        if (n.inverseMass[i] == 0) {
            pinned_.push_back(i);  // reserved for every node
            inverseBlock_[i].setZero();
            rhs_[i].setZero();
            continue;
        }
        Mat3 block = inverseBlock_[i];
        block.diagonal().array() += nodeDiagonal_[i];
        inverseBlock_[i] = block.inverse();  // positive definite: the mass alone makes it so
    }
}

void BackwardEulerSystem::multiply(std::span<const Vec3> y, std::span<Vec3> out) const {
    for (std::uint32_t i : region_.touched) out[i] = nodeDiagonal_[i] * y[i];
    const std::vector<std::uint32_t>& ends_a = springs_->a;
    const std::vector<std::uint32_t>& ends_b = springs_->b;
    for (std::uint32_t e : region_.springs) {
        const std::uint32_t a = ends_a[e], b = ends_b[e];
        const Vec3& u = springAxis_[e];
        const Vec3 dy = y[a] - y[b];
        const Vec3 t = springScalar_[e] * dy + u.dot(dy) * u;
        out[a] += t;
        out[b] -= t;
    }
    for (std::uint32_t i : pinned_) out[i].setZero();
}

void BackwardEulerSystem::precondition(std::span<const Vec3> r, std::span<Vec3> z) const {
    for (std::uint32_t i : region_.nodes) z[i] = inverseBlock_[i] * r[i];
}

}  // namespace hapticut::physics
