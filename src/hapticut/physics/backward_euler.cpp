// The preconditioned conjugate-gradient solve and the update of one backward-Euler step.
#include "hapticut/physics/backward_euler.h"

#include <algorithm>
#include <cmath>

#include "hapticut/common/reserve.h"

namespace hapticut::physics {

void BackwardEuler::reserve(std::size_t nodes, std::size_t springs) {
    system_.reserve(nodes, springs);
    for (auto* v : {&deltaV_, &startVelocity_, &motion_}) reserveTouched(*v, nodes);
    for (auto* field : {&solution_, &residual_, &preconditioned_, &direction_, &product_})
        for (auto* a : {&field->x, &field->y, &field->z}) reserveTouched(*a, nodes + kernels::kSliceRows);
}

void BackwardEuler::resize(std::size_t nodes) {
    system_.resize(nodes);
    deltaV_.resize(std::max(nodes, deltaV_.size()), Vec3::Zero());
}

void BackwardEuler::setSettings(SolverSettings settings) {
    settings.maxIterations = std::clamp(settings.maxIterations, 1, kMaxSolverIterations);
    settings.maxNewtonIterations = std::clamp(settings.maxNewtonIterations, 1, 100);
    settings.forceTolerance_N = std::max(settings.forceTolerance_N, 0.0);
    settings_ = settings;
}

SolveReport BackwardEuler::step(MassSpringModel& model, double h, SolveRegion region) {
    Nodes& n = model.nodes;
    const std::size_t count = region.nodes.size();
    h_ = h;
    // Capacity is reserved for every node: these never allocate in a step.
    startVelocity_.resize(count);
    motion_.resize(count);
    for (std::size_t k = 0; k < count; ++k) startVelocity_[k] = n.velocity[region.nodes[k]];
    system_.assemble(model, h, region);
    for (auto* field : {&solution_, &residual_, &preconditioned_, &direction_, &product_})
        field->resize(system_.rows());
    for (std::size_t k = 0; k < system_.rows(); ++k) {  // the warm start; zero on the padding rows
        const Vec3 guess = k < count ? deltaV_[region.nodes[k]] : Vec3::Zero();
        solution_.x[k] = guess.x(), solution_.y[k] = guess.y(), solution_.z[k] = guess.z();
    }
    double stepNorm2 = 0;  // set by the first solve, the measure of the corrections
    SolveReport report = solve(stepNorm2);
    auto apply = [&](bool whole) {
        for (std::size_t k = 0; k < count; ++k) {
            const std::uint32_t i = region.nodes[k];
            const Vec3 change(solution_.x[k], solution_.y[k], solution_.z[k]);
            n.velocity[i] += change;
            // The first iteration moves by the whole new velocity, a correction by its change.
            motion_[k] = h * (whole ? n.velocity[i] : change);
            n.position[i] += motion_[k];
        }
    };
    apply(true);
    // Newton's corrections, solved with the matrix at the latest iterate x = x0 + h v, while the last
    // iteration moved the springs too far for its linearisation to hold.
    while (report.newtonIterations < settings_.maxNewtonIterations &&
           system_.largestRelativeMotion(model.springs, region, motion_) > kLinearMotion) {
        system_.assemble(model, h, region, startVelocity_);
        for (auto* a : {&solution_.x, &solution_.y, &solution_.z}) std::fill(a->begin(), a->end(), 0.0);
        const SolveReport correction = solve(stepNorm2);
        report.iterations += correction.iterations;
        report.relativeResidual = correction.relativeResidual;
        report.converged = report.converged && correction.converged;
        ++report.newtonIterations;
        apply(false);
    }
    for (std::size_t k = 0; k < count; ++k) deltaV_[region.nodes[k]] = n.velocity[region.nodes[k]] - startVelocity_[k];
    return report;
}

SolveReport BackwardEuler::solve(double& stepNorm2) {
    const std::size_t rows = system_.rows();
    const kernels::Field& b = system_.rhs();
    const kernels::SystemRows matrix = system_.matrix();
    const kernels::SymmetricBlocks& inverse = system_.inverseBlocks();
    SolveReport report;
    double bNorm2 = 0;
    for (std::size_t k = 0; k < rows; ++k) bNorm2 += b.x[k] * b.x[k] + b.y[k] * b.y[k] + b.z[k] * b.z[k];
    if (bNorm2 == 0) {
        for (auto* a : {&solution_.x, &solution_.y, &solution_.z}) std::fill(a->begin(), a->end(), 0.0);
        return report;
    }
    if (stepNorm2 > 0)
        bNorm2 = stepNorm2;
    else
        stepNorm2 = bNorm2;
    const double forceFloor = settings_.forceTolerance_N * h_;
    const double stop2 = std::max(settings_.tolerance * settings_.tolerance * bNorm2, forceFloor * forceFloor);

    // Each iteration is one product and two passes over the unknowns, with the dot products fused in.
    // The warm start g is scaled along its line to the point nearest the solution in the A-norm,
    // s = gᵀb / gᵀAg: never a worse start than zero, which the raw last change of velocity can be by
    // several times where the tissue rings or the step size changes (multi-rate steps vary).
    const double gAg = kernels::multiply(matrix, solution_, product_);
    if (gAg > 0 && std::isfinite(gAg)) {
        double gb = 0;
        for (std::size_t k = 0; k < rows; ++k)
            gb += solution_.x[k] * b.x[k] + solution_.y[k] * b.y[k] + solution_.z[k] * b.z[k];
        const double scale = gb / gAg;
        for (kernels::Field* field : {&solution_, &product_})
            for (auto* a : {&field->x, &field->y, &field->z})
                for (double& value : *a) value *= scale;
    }
    kernels::Sums sums = kernels::startPass(rows, b, product_, inverse, residual_, preconditioned_, direction_);
    double r2 = sums.r2, rz = sums.rz;
    while (r2 > stop2 && report.iterations < settings_.maxIterations) {
        const double pq = kernels::multiply(matrix, direction_, product_);
        if (!(pq > 0) || !std::isfinite(pq)) break;  // a breakdown: keep what was reached
        sums = kernels::updatePass(rows, rz / pq, direction_, product_, inverse, solution_, residual_, preconditioned_);
        r2 = sums.r2;
        ++report.iterations;
        if (r2 <= stop2) break;
        kernels::directionPass(rows, sums.rz / rz, preconditioned_, direction_);
        rz = sums.rz;
    }
    report.relativeResidual = std::sqrt(r2 / bNorm2);
    report.converged = r2 <= stop2;
    return report;
}

}  // namespace hapticut::physics
