// The preconditioned conjugate-gradient solve and the update of one backward-Euler step.
#include "hapticut/physics/backward_euler.h"

#include <algorithm>
#include <cmath>

#include "hapticut/common/reserve.h"

namespace hapticut::physics {

void BackwardEuler::reserve(std::size_t nodes, std::size_t springs) {
    system_.reserve(nodes, springs);
    for (auto* v : {&deltaV_, &residual_, &preconditioned_, &direction_, &product_}) reserveTouched(*v, nodes);
}

void BackwardEuler::resize(std::size_t nodes, std::size_t springs) {
    system_.resize(nodes, springs);
    for (auto* v : {&deltaV_, &residual_, &preconditioned_, &direction_, &product_})
        v->resize(std::max(nodes, v->size()), Vec3::Zero());
}

void BackwardEuler::setSettings(SolverSettings settings) {
    settings.maxIterations = std::clamp(settings.maxIterations, 1, kMaxSolverIterations);
    settings_ = settings;
}

SolveReport BackwardEuler::step(MassSpringModel& model, double h, SolveRegion region) {
    system_.assemble(model, h, region);
    const SolveReport report = solve();
    Nodes& n = model.nodes;
    for (std::uint32_t i : region.nodes) {
        n.velocity[i] += deltaV_[i];
        n.position[i] += h * n.velocity[i];
    }
    return report;
}

SolveReport BackwardEuler::solve() {
    const SolveRegion& region = system_.region();
    const std::span<const Vec3> b = system_.rhs();
    auto dot = [&](const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
        double sum = 0;
        for (std::uint32_t i : region.nodes) sum += p[i].dot(q[i]);
        return sum;
    };
    // The products read the resting neighbours' entries, which must be zero; a node awake in an earlier
    // step may have left values there. This zeroes them while keeping the awake nodes' warm start.
    for (std::uint32_t i : region.touched) direction_[i].setZero();
    for (std::uint32_t i : region.nodes) direction_[i] = deltaV_[i];
    for (std::uint32_t i : region.touched) deltaV_[i] = direction_[i];

    double bNorm2 = 0;
    for (std::uint32_t i : region.nodes) bNorm2 += b[i].squaredNorm();
    SolveReport report;
    if (bNorm2 == 0) {
        for (std::uint32_t i : region.nodes) deltaV_[i].setZero();
        return report;
    }
    const double stop2 = settings_.tolerance * settings_.tolerance * bNorm2;

    system_.multiply(deltaV_, product_);
    double r2 = 0;
    for (std::uint32_t i : region.nodes) {
        residual_[i] = b[i] - product_[i];
        r2 += residual_[i].squaredNorm();
    }
    system_.precondition(residual_, preconditioned_);
    for (std::uint32_t i : region.nodes) direction_[i] = preconditioned_[i];
    double rz = dot(residual_, preconditioned_);
    while (r2 > stop2 && report.iterations < settings_.maxIterations) {
        system_.multiply(direction_, product_);
        const double pq = dot(direction_, product_);
        if (!(pq > 0) || !std::isfinite(pq)) break;  // a breakdown: keep what was reached
        const double step = rz / pq;
        r2 = 0;
        for (std::uint32_t i : region.nodes) {
            deltaV_[i] += step * direction_[i];
            residual_[i] -= step * product_[i];
            r2 += residual_[i].squaredNorm();
        }
        ++report.iterations;
        if (r2 <= stop2) break;
        system_.precondition(residual_, preconditioned_);
        const double rzNext = dot(residual_, preconditioned_);
        const double beta = rzNext / rz;
        rz = rzNext;
        for (std::uint32_t i : region.nodes) direction_[i] = preconditioned_[i] + beta * direction_[i];
    }
    report.relativeResidual = std::sqrt(r2 / bNorm2);
    report.converged = r2 <= stop2;
    return report;
}

}  // namespace hapticut::physics
