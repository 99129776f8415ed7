// Assembly and products of the backward-Euler system.
#include "hapticut/physics/backward_euler_system.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "hapticut/common/reserve.h"

namespace hapticut::physics {

void BackwardEulerSystem::reserve(std::size_t nodes, std::size_t springs) {
    reserveTouched(unknownOf_, nodes);
    reserveTouched(diagonal_, nodes);
    reserveTouched(toResting_, nodes);
    reserveTouched(rowStart_, nodes + 1);
    reserveTouched(couplings_, 2 * springs);
    reserveTouched(inverseBlock_, nodes);
    reserveTouched(blockSum_, nodes);
    reserveTouched(restingSum_, nodes);
    reserveTouched(rhs_, nodes);
    reserveTouched(pinned_, nodes);
}

void BackwardEulerSystem::resize(std::size_t nodes) { unknownOf_.resize(std::max(nodes, unknownOf_.size()), kResting); }

BackwardEulerSystem::SymmetricBlock BackwardEulerSystem::toSymmetricBlock(const Mat3& m) {
    const auto f = [](double value) { return static_cast<float>(value); };
    return {f(m(0, 0)), f(m(0, 1)), f(m(0, 2)), f(m(1, 1)), f(m(1, 2)), f(m(2, 2))};
}

void BackwardEulerSystem::assemble(const MassSpringModel& model, double h, SolveRegion region,
                                   std::span<const Vec3> startVelocity) {
    // The first linearisation adds h² K v to the right-hand side; a correction subtracts M (v - v0).
    const bool correction = !startVelocity.empty();
    const Nodes& n = model.nodes;
    const Springs& s = model.springs;
    const std::vector<Vec3>& x = n.position;
    const std::vector<Vec3>& v = n.velocity;
    const double h2 = h * h;
    // Capacity is reserved for every node and spring: these resizes never allocate in a step.
    const std::size_t count = region.nodes.size();
    diagonal_.resize(count);
    toResting_.resize(count);
    inverseBlock_.resize(count);
    blockSum_.resize(count);
    restingSum_.resize(count);
    rhs_.resize(count);
    rowStart_.assign(count + 1, 0);
    for (std::uint32_t i : region.touched) unknownOf_[i] = kResting;
    const Vec3 g = model.gravity_m_per_s2;
    for (std::uint32_t k = 0; k < count; ++k) {
        const std::uint32_t i = region.nodes[k];
        unknownOf_[i] = k;
        const double ka = n.anchorStiffness[i], da = n.anchorDamping[i];
        const Vec3 f = n.externalForce[i] - ka * (x[i] - n.restPosition[i]) - da * v[i] +
                       (n.inverseMass[i] > 0 ? Vec3(n.mass[i] * g) : Vec3::Zero());
        rhs_[k] = h * f - (correction ? Vec3(n.mass[i] * (v[i] - startVelocity[k])) : Vec3(h2 * ka * v[i]));
        diagonal_[k] = n.mass[i] + h * da + h2 * ka;
        blockSum_[k].setZero();
        restingSum_[k].setZero();
    }
    for (const PointSpring& tool : model.tools) {
        if (!tool.active) continue;
        const Vec3 force = tool.forceOnTool(x);
        // A clamped force no longer grows with the press: its stiffness is left out of the matrix.
        const Vec3 p =
            tool.bary.x() * x[tool.nodes[0]] + tool.bary.y() * x[tool.nodes[1]] + tool.bary.z() * x[tool.nodes[2]];
        const bool linear = force != Vec3::Zero() &&
                            (tool.stiffness_N_per_m * (p - tool.anchor_m) - tool.bias_N).norm() <= tool.maxForce_N;
        const double kt = linear ? tool.scale * tool.stiffness_N_per_m : 0.0;
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t k = unknownOf_[tool.nodes[c]];
            if (k == kResting) continue;  // the active region keeps a tool's nodes awake; a full solve has all
            const double w = tool.weights[c];
            rhs_[k] -= h * w * force + (correction ? Vec3::Zero() : Vec3(h2 * kt * w * v[tool.nodes[c]]));
            diagonal_[k] += h2 * kt * w;
        }
    }
    // The rows' lengths first, so that each row's couplings can be written in place.
    for (std::uint32_t e : region.springs) {
        const std::uint32_t ka = unknownOf_[s.a[e]], kb = unknownOf_[s.b[e]];
        if (ka != kResting && kb != kResting) ++rowStart_[ka + 1], ++rowStart_[kb + 1];
    }
    for (std::size_t k = 0; k < count; ++k) rowStart_[k + 1] += rowStart_[k];
    couplings_.resize(rowStart_[count]);
    std::uint32_t* next = rowStart_.data();  // each row's next free slot; rowStart_[k] ends at row k's end
    auto rowEnd = [&](std::uint32_t k) { return next[k]++; };
    for (std::uint32_t e : region.springs) {
        const std::uint32_t a = s.a[e], b = s.b[e];
        const Vec3 d = x[b] - x[a];
        const double len2 = d.squaredNorm();
        const std::uint32_t ka = unknownOf_[a], kb = unknownOf_[b];
        const bool inner = ka != kResting && kb != kResting;
        if (len2 < 1e-24) {  // coincident ends have no direction, as in the explicit force
            if (inner) couplings_[rowEnd(ka)] = {kb, 0, 0, 0, 0}, couplings_[rowEnd(kb)] = {ka, 0, 0, 0, 0};
            continue;
        }
        const double len = std::sqrt(len2);
        const Vec3 dir = d / len;
        const Vec3 dv = v[b] - v[a];
        const double ks = s.stiffness[e], kd = s.damping[e];
        const Vec3 force = (ks * (len - s.restLength[e]) + kd * dv.dot(dir)) * dir;  // on a
        const double alpha = std::max(0.0, 1 - s.restLength[e] / len);
        const Vec3 contribution =
            h * force + (correction ? Vec3::Zero() : Vec3(h2 * ks * (alpha * dv + (1 - alpha) * dir.dot(dv) * dir)));
        const double c0 = h2 * ks * alpha;
        const Vec3 u = std::sqrt(h2 * ks * (1 - alpha) + h * kd) * dir;
        const Mat3 block = c0 * Mat3::Identity() + u * u.transpose();
        if (ka != kResting) rhs_[ka] += contribution, blockSum_[ka] += block;
        if (kb != kResting) rhs_[kb] -= contribution, blockSum_[kb] += block;
        if (inner) {
            const auto f = [](double value) { return static_cast<float>(value); };
            couplings_[rowEnd(ka)] = {kb, f(c0), f(u.x()), f(u.y()), f(u.z())};
            couplings_[rowEnd(kb)] = {ka, f(c0), f(u.x()), f(u.y()), f(u.z())};
        } else {
            restingSum_[ka != kResting ? ka : kb] += block;
        }
    }
    // The filling moved each row's start to its end: move them back.
    for (std::size_t k = count; k > 0; --k) rowStart_[k] = rowStart_[k - 1];
    rowStart_[0] = 0;
    pinned_.clear();
    for (std::uint32_t k = 0; k < count; ++k) {
        toResting_[k] = toSymmetricBlock(restingSum_[k]);
        if (n.inverseMass[region.nodes[k]] == 0) {
            pinned_.push_back(k);
            inverseBlock_[k] = {};
            rhs_[k].setZero();
            continue;
        }
        Mat3 block = blockSum_[k];
        block.diagonal().array() += diagonal_[k];
        inverseBlock_[k] = toSymmetricBlock(block.inverse());  // positive definite: the mass alone makes it so
    }
}

double BackwardEulerSystem::largestRelativeMotion(const Springs& springs, SolveRegion region,
                                                  std::span<const Vec3> motion) const {
    double largest2 = 0;
    for (std::uint32_t e : region.springs) {
        const double rest = springs.restLength[e];
        if (rest < 1e-9) continue;
        const std::uint32_t ka = unknownOf_[springs.a[e]], kb = unknownOf_[springs.b[e]];
        const Vec3 ma = ka != kResting ? motion[ka] : Vec3::Zero(), mb = kb != kResting ? motion[kb] : Vec3::Zero();
        largest2 = std::max(largest2, (mb - ma).squaredNorm() / (rest * rest));
    }
    return std::sqrt(largest2);
}

double BackwardEulerSystem::multiply(std::span<const Vec3> y, std::span<Vec3> out) const {
    // Row by row: each unknown's sum builds up in registers and is stored once. yᵀAy is summed on the way.
    double yAy = 0;
    const std::size_t count = rhs_.size();
    for (std::size_t k = 0; k < count; ++k) {
        const Vec3 yk = y[k];
        Vec3 sum = diagonal_[k] * yk + toResting_[k] * yk;
        for (std::uint32_t c = rowStart_[k], end = rowStart_[k + 1]; c < end; ++c) {
            const Coupling& s = couplings_[c];
            const Vec3 dy = yk - y[s.other];
            const Vec3 u(s.ux, s.uy, s.uz);
            sum += s.c0 * dy + u.dot(dy) * u;
        }
        out[k] = sum;
        yAy += yk.dot(sum);
    }
    for (std::uint32_t k : pinned_) out[k].setZero();  // their y is zero: no share in yᵀAy
    return yAy;
}

}  // namespace hapticut::physics
