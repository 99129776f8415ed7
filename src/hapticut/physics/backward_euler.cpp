// The preconditioned conjugate-gradient solve and the update of one backward-Euler step.
#include "hapticut/physics/backward_euler.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>

#include "hapticut/common/reserve.h"

namespace hapticut::physics {

std::string_view preconditionerName(Preconditioner p) {
    switch (p) {
        case Preconditioner::Auto: return "auto";
        case Preconditioner::BlockJacobi: return "block-jacobi";
        case Preconditioner::Multilevel: return "multilevel";
    }
    return "auto";
}

std::optional<Preconditioner> parsePreconditioner(std::string_view name) {
    for (Preconditioner p : {Preconditioner::Auto, Preconditioner::BlockJacobi, Preconditioner::Multilevel})
        if (preconditionerName(p) == name) return p;
    return std::nullopt;
}

unsigned automaticSolverThreads() {
    return std::max(1u, WorkerPool::hardwareThreads() - std::min(2u, WorkerPool::hardwareThreads()));
}

unsigned solverThreads(unsigned threads) {
    return std::min(threads == 0 ? automaticSolverThreads() : threads, kMaxSolverThreads);
}

void BackwardEuler::reserve(std::size_t nodes, std::size_t springs) {
    system_.reserve(nodes, springs);
    for (auto* v : {&deltaV_, &startVelocity_, &motion_}) reserveTouched(*v, nodes);
    for (auto* field : {&solution_, &residual_, &preconditioned_, &direction_, &product_})
        for (auto* a : {&field->x, &field->y, &field->z}) reserveTouched(*a, nodes + kernels::kSliceRows);
    reserveTouched(partial_, nodes / kernels::kChunkRows + 2);
    multilevel_.reserve(nodes, system_.slotCapacity());
    multilevelLayout_ = 0;  // its levels are laid out again at the next step
}

void BackwardEuler::resize(std::size_t nodes) {
    system_.resize(nodes);
    deltaV_.resize(std::max(nodes, deltaV_.size()), Vec3::Zero());
}

void BackwardEuler::setSettings(SolverSettings settings) {
    settings.maxIterations = std::clamp(settings.maxIterations, 1, kMaxSolverIterations);
    settings.maxNewtonIterations = std::clamp(settings.maxNewtonIterations, 1, 100);
    settings.forceTolerance_N = std::max(settings.forceTolerance_N, 0.0);
    pool_.resize(solverThreads(settings.threads));
    settings_ = settings;
}

template <class Task>
void BackwardEuler::forEachChunk(std::size_t size, Task&& task) {
    pool_.forEach(kernels::chunksOf(size), [&](std::size_t chunk) {
        const kernels::RowRange range = kernels::chunkRows(chunk, size);
        task(range.first, range.end);
    });
}

namespace {

/// The chunks' sums, added in chunk order whichever thread computed each.
kernels::Sums total(std::span<const kernels::Sums> partial) {
    kernels::Sums sums;
    for (const kernels::Sums& part : partial)
        sums.r2 += part.r2, sums.rz += part.rz, sums.rowMax2 = std::max(sums.rowMax2, part.rowMax2);
    return sums;
}

std::size_t chunkOf(std::size_t firstRow) { return firstRow / kernels::kChunkRows; }

}  // namespace

double BackwardEuler::multiply(const kernels::Field& y, kernels::Field& out) {
    const kernels::SystemRows matrix = system_.matrix();
    forEachChunk(matrix.rows, [&](std::size_t first, std::size_t end) {
        partial_[chunkOf(first)] = {kernels::multiply(matrix, y, out, {first, end}), 0};
    });
    return total(partial_).r2;
}

SolveReport BackwardEuler::step(MassSpringModel& model, double h, SolveRegion region) {
    const auto start = std::chrono::steady_clock::now();
    Nodes& n = model.nodes;
    const std::size_t count = region.nodes.size();
    h_ = h;
    // Capacity is reserved for every node: these never allocate in a step.
    startVelocity_.resize(count);
    motion_.resize(count);
    const std::size_t rows = (count + kernels::kSliceRows - 1) / kernels::kSliceRows * kernels::kSliceRows;
    for (auto* field : {&solution_, &residual_, &preconditioned_, &direction_, &product_}) field->resize(rows);
    // Every pass over the unknowns runs in chunks of rows on the pool's threads.
    forEachChunk(rows, [&](std::size_t first, std::size_t end) {
        // The arrays held here, as in apply below: through the captures, every store reloaded them.
        const std::uint32_t* __restrict nodes = region.nodes.data();
        const Vec3* __restrict lastChange = deltaV_.data();
        const Vec3* __restrict velocity = n.velocity.data();
        Vec3* __restrict startVelocity = startVelocity_.data();
        double* __restrict sx = solution_.x.data();
        double* __restrict sy = solution_.y.data();
        double* __restrict sz = solution_.z.data();
        for (std::size_t k = first; k < end; ++k) {  // the warm start; zero on the padding rows
            const Vec3 guess = k < count ? lastChange[nodes[k]] : Vec3::Zero();
            sx[k] = guess.x(), sy[k] = guess.y(), sz[k] = guess.z();
            if (k < count) startVelocity[k] = velocity[nodes[k]];
        }
    });
    const Preconditioner chosen = settings_.preconditioner;
    if (count < kMultilevelUnknowns) autoMultilevel_ = false;
    useMultilevel_ = chosen == Preconditioner::Multilevel || (chosen == Preconditioner::Auto && autoMultilevel_);
    assemble(model, h, region, {});
    double stepNorm2 = 0;  // set by the first solve, the measure of the corrections
    SolveReport report = solve(stepNorm2);
    const int firstIterations = report.iterations;
    const bool firstConverged = report.converged;
    auto apply = [&](bool whole) {
        forEachChunk(count, [&](std::size_t first, std::size_t end) {
            // The arrays held here: through the captures, every store made the loop load their addresses
            // again (the step's own passes were 11% of a 9,714 heart's step, 8% since).
            const std::uint32_t* __restrict nodes = region.nodes.data();
            const double* __restrict sx = solution_.x.data();
            const double* __restrict sy = solution_.y.data();
            const double* __restrict sz = solution_.z.data();
            Vec3* __restrict velocity = n.velocity.data();
            Vec3* __restrict position = n.position.data();
            Vec3* __restrict motion = motion_.data();
            for (std::size_t k = first; k < end; ++k) {
                const std::uint32_t i = nodes[k];
                const Vec3 change(sx[k], sy[k], sz[k]);
                const Vec3 v = velocity[i] + change;
                velocity[i] = v;
                // The first iteration moves by the whole new velocity, a correction by its change.
                const Vec3 m = h * (whole ? v : change);
                motion[k] = m;
                position[i] += m;
            }
        });
    };
    apply(true);
    // Newton's corrections, solved with the matrix at the latest iterate x = x0 + h v, while the last
    // iteration moved the springs too far for its linearisation to hold, and, when keeping pace, while
    // one more iteration like the ones so far still fits in the step's share of the wall clock.
    auto fitsOneMore = [&] {
        if (paceShare_ <= 0) return true;
        const double spent_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return spent_s * (report.newtonIterations + 1) / report.newtonIterations <= paceShare_ * h;
    };
    while (report.newtonIterations < settings_.maxNewtonIterations &&
           system_.movesApartMoreThan(model.springs, region, motion_, kLinearMotion, &pool_)) {
        if (!fitsOneMore()) {
            report.newtonCutShort = true;
            break;
        }
        assemble(model, h, region, startVelocity_);
        forEachChunk(rows, [&](std::size_t first, std::size_t end) {
            for (auto* a : {&solution_.x, &solution_.y, &solution_.z}) std::fill(&(*a)[first], &(*a)[end], 0.0);
        });
        const SolveReport correction = solve(stepNorm2);
        report.iterations += correction.iterations;
        report.relativeResidual = correction.relativeResidual;
        report.converged = report.converged && correction.converged;
        ++report.newtonIterations;
        apply(false);
    }
    // Auto's rule for the next steps (backward_euler.h); the region's size was checked above.
    if (chosen == Preconditioner::Auto && !useMultilevel_) {
        multilevelPause_ = std::max(0, multilevelPause_ - 1);
        const bool hard = firstIterations > kJacobiIterationsForMultilevel && multilevelPause_ == 0;
        autoMultilevel_ = count >= kMultilevelUnknowns && (hard || !firstConverged);
        jacobiIterations_ = firstConverged ? firstIterations : 0;
    } else if (chosen == Preconditioner::Auto && jacobiIterations_ > 0 &&
               kMultilevelIterationCost * firstIterations >= jacobiIterations_) {
        autoMultilevel_ = false;
        multilevelPause_ = kMultilevelPause;
    }
    forEachChunk(count, [&](std::size_t first, std::size_t end) {
        const std::uint32_t* __restrict nodes = region.nodes.data();
        const Vec3* __restrict velocity = n.velocity.data();
        const Vec3* __restrict startVelocity = startVelocity_.data();
        Vec3* __restrict change = deltaV_.data();
        for (std::size_t k = first; k < end; ++k) change[nodes[k]] = velocity[nodes[k]] - startVelocity[k];
    });
    return report;
}

void BackwardEuler::assemble(MassSpringModel& model, double h, SolveRegion region,
                             std::span<const Vec3> startVelocity) {
    system_.assemble(model, h, region, startVelocity, &pool_);
    if (!useMultilevel_) return;
    if (multilevelLayout_ != system_.layoutsMade() || !multilevel_.laidOut()) {
        multilevel_.layOut(system_.matrix(), system_.size());
        multilevelLayout_ = system_.layoutsMade();
    }
    multilevel_.assemble(system_.matrix());
}

SolveReport BackwardEuler::solve(double& stepNorm2) {
    const std::size_t rows = system_.rows();
    const kernels::Field& b = system_.rhs();
    const kernels::SymmetricBlocks& inverse = system_.inverseBlocks();
    partial_.resize(kernels::chunksOf(rows));
    SolveReport report;
    report.multilevel = useMultilevel_;
    // x·b, or b·b with x = b: the chunks' parts added in chunk order.
    auto dot = [&](const kernels::Field& x) {
        forEachChunk(rows, [&](std::size_t first, std::size_t end) {
            double sum = 0;
            for (std::size_t k = first; k < end; ++k) sum += x.x[k] * b.x[k] + x.y[k] * b.y[k] + x.z[k] * b.z[k];
            partial_[chunkOf(first)] = {sum, 0};
        });
        return total(partial_).r2;
    };
    double bNorm2 = dot(b);
    if (bNorm2 == 0) {
        for (auto* a : {&solution_.x, &solution_.y, &solution_.z}) std::fill(a->begin(), a->end(), 0.0);
        return report;
    }
    if (stepNorm2 > 0)
        bNorm2 = stepNorm2;
    else
        stepNorm2 = bNorm2;
    const double stop2 = settings_.tolerance * settings_.tolerance * bNorm2;
    const double forceFloor = settings_.forceTolerance_N * h_;  // on every row's residual
    auto done = [&](const kernels::Sums& sums) { return sums.r2 <= stop2 || sums.rowMax2 <= forceFloor * forceFloor; };

    // Each iteration is one product and two passes over the unknowns, with the dot products fused in.
    // The warm start g is scaled along its line to the point nearest the solution in the A-norm,
    // s = gᵀb / gᵀAg: never a worse start than zero, which the raw last change of velocity can be by
    // several times where the tissue rings or the step size changes (multi-rate steps vary).
    const double gAg = multiply(solution_, product_);
    if (gAg > 0 && std::isfinite(gAg)) {
        const double scale = dot(solution_) / gAg;
        forEachChunk(rows, [&](std::size_t first, std::size_t end) {
            for (kernels::Field* field : {&solution_, &product_})
                for (auto* a : {&field->x, &field->y, &field->z})
                    for (std::size_t k = first; k < end; ++k) (*a)[k] *= scale;
        });
    }
    // With the multilevel preconditioner z is its cycle's, which begins with the passes' z weighted for smoothing.
    const double weight = useMultilevel_ ? multilevel_.firstWeight() : 1.0;
    forEachChunk(rows, [&](std::size_t first, std::size_t end) {
        partial_[chunkOf(first)] =
            kernels::startPass({first, end}, b, product_, inverse, residual_, preconditioned_, direction_, weight);
    });
    kernels::Sums sums = total(partial_);
    const kernels::SystemRows matrix = system_.matrix();
    auto precondition = [&] { sums = multilevel_.apply(matrix, inverse, residual_, preconditioned_, pool_, true); };
    if (useMultilevel_) {
        precondition();
        forEachChunk(rows, [&](std::size_t first, std::size_t end) {
            for (auto [from, to] :
                 {std::pair{&preconditioned_.x, &direction_.x}, std::pair{&preconditioned_.y, &direction_.y},
                  std::pair{&preconditioned_.z, &direction_.z}})
                std::copy(&(*from)[first], &(*from)[end], &(*to)[first]);
        });
    }
    double rz = sums.rz;
    while (!done(sums) && report.iterations < settings_.maxIterations) {
        const double pq = multiply(direction_, product_);
        if (!(pq > 0) || !std::isfinite(pq)) break;  // a breakdown: keep what was reached
        const double alpha = rz / pq;
        forEachChunk(rows, [&](std::size_t first, std::size_t end) {
            partial_[chunkOf(first)] = kernels::updatePass({first, end}, alpha, direction_, product_, inverse,
                                                           solution_, residual_, preconditioned_, weight);
        });
        sums = total(partial_);
        ++report.iterations;
        if (done(sums)) break;
        if (useMultilevel_) precondition();
        const double beta = sums.rz / rz;
        forEachChunk(rows, [&](std::size_t first, std::size_t end) {
            kernels::directionPass({first, end}, beta, preconditioned_, direction_);
        });
        rz = sums.rz;
    }
    report.relativeResidual = std::sqrt(sums.r2 / bNorm2);
    report.converged = done(sums);
    return report;
}

}  // namespace hapticut::physics
