// The preconditioned conjugate-gradient solve and the update of one backward-Euler step.
#include "hapticut/physics/backward_euler.h"

#include <algorithm>
#include <cmath>

#include "hapticut/common/reserve.h"

namespace hapticut::physics {

void BackwardEuler::reserve(std::size_t nodes, std::size_t springs) {
    system_.reserve(nodes, springs);
    for (auto* v :
         {&deltaV_, &startVelocity_, &motion_, &solution_, &residual_, &preconditioned_, &direction_, &product_})
        reserveTouched(*v, nodes);
}

void BackwardEuler::resize(std::size_t nodes) {
    system_.resize(nodes);
    deltaV_.resize(std::max(nodes, deltaV_.size()), Vec3::Zero());
}

void BackwardEuler::setSettings(SolverSettings settings) {
    settings.maxIterations = std::clamp(settings.maxIterations, 1, kMaxSolverIterations);
    settings.maxNewtonIterations = std::clamp(settings.maxNewtonIterations, 1, 100);
    settings_ = settings;
}

SolveReport BackwardEuler::step(MassSpringModel& model, double h, SolveRegion region) {
    Nodes& n = model.nodes;
    const std::size_t count = region.nodes.size();
    // Capacity is reserved for every node: these never allocate in a step.
    for (auto* v : {&startVelocity_, &motion_, &solution_, &residual_, &preconditioned_, &direction_, &product_})
        v->resize(count);
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t i = region.nodes[k];
        startVelocity_[k] = n.velocity[i];
        solution_[k] = deltaV_[i];  // the warm start
    }
    system_.assemble(model, h, region);
    SolveReport report = solve();
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t i = region.nodes[k];
        n.velocity[i] += solution_[k];
        motion_[k] = h * n.velocity[i];
        n.position[i] += motion_[k];
    }
    // Newton's corrections, solved with the matrix at the latest iterate x = x0 + h v, while the last
    // iteration moved the springs too far for its linearisation to hold.
    while (report.newtonIterations < settings_.maxNewtonIterations &&
           system_.largestRelativeMotion(model.springs, region, motion_) > kLinearMotion) {
        system_.assemble(model, h, region, startVelocity_);
        std::fill(solution_.begin(), solution_.end(), Vec3::Zero());
        const SolveReport correction = solve();
        report.iterations += correction.iterations;
        report.relativeResidual = correction.relativeResidual;
        report.converged = report.converged && correction.converged;
        ++report.newtonIterations;
        for (std::size_t k = 0; k < count; ++k) {
            const std::uint32_t i = region.nodes[k];
            n.velocity[i] += solution_[k];
            motion_[k] = h * solution_[k];
            n.position[i] += motion_[k];
        }
    }
    for (std::size_t k = 0; k < count; ++k) deltaV_[region.nodes[k]] = n.velocity[region.nodes[k]] - startVelocity_[k];
    return report;
}

SolveReport BackwardEuler::solve() {
    const std::size_t count = system_.size();
    const std::span<const Vec3> b = system_.rhs();
    SolveReport report;
    double bNorm2 = 0;
    for (const Vec3& bk : b) bNorm2 += bk.squaredNorm();
    if (bNorm2 == 0) {
        std::fill(solution_.begin(), solution_.end(), Vec3::Zero());
        return report;
    }
    const double stop2 = settings_.tolerance * settings_.tolerance * bNorm2;

    // Each iteration is one product and two passes over the unknowns, with the dot products fused in.
    (void)system_.multiply(solution_, product_);
    double r2 = 0, rz = 0;
    for (std::size_t k = 0; k < count; ++k) {
        residual_[k] = b[k] - product_[k];
        direction_[k] = system_.precondition(k, residual_[k]);
        r2 += residual_[k].squaredNorm();
        rz += residual_[k].dot(direction_[k]);
    }
    while (r2 > stop2 && report.iterations < settings_.maxIterations) {
        const double pq = system_.multiply(direction_, product_);
        if (!(pq > 0) || !std::isfinite(pq)) break;  // a breakdown: keep what was reached
        const double alpha = rz / pq;
        double rzNext = 0;
        r2 = 0;
        for (std::size_t k = 0; k < count; ++k) {
            solution_[k] += alpha * direction_[k];
            residual_[k] -= alpha * product_[k];
            preconditioned_[k] = system_.precondition(k, residual_[k]);
            r2 += residual_[k].squaredNorm();
            rzNext += residual_[k].dot(preconditioned_[k]);
        }
        ++report.iterations;
        if (r2 <= stop2) break;
        const double beta = rzNext / rz;
        rz = rzNext;
        for (std::size_t k = 0; k < count; ++k) direction_[k] = preconditioned_[k] + beta * direction_[k];
    }
    report.relativeResidual = std::sqrt(r2 / bNorm2);
    report.converged = r2 <= stop2;
    return report;
}

}  // namespace hapticut::physics
