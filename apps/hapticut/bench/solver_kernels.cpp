// Timing the physics' SIMD kernels under each instruction set.
#include "bench/solver_kernels.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "hapticut/common/stats.h"
#include "hapticut/physics/backward_euler_system.h"
#include "hapticut/physics/solver_kernels.h"
#include "hapticut/physics/spring_forces.h"

namespace hapticut::bench {

std::vector<KernelTiming> timeSolverKernels(const physics::MassSpringModel& model, double seconds) {
    using Clock = std::chrono::steady_clock;
    std::vector<std::uint32_t> nodes(model.nodes.size()), springs(model.springs.size());
    std::iota(nodes.begin(), nodes.end(), 0u);
    std::iota(springs.begin(), springs.end(), 0u);
    physics::BackwardEulerSystem system;
    system.reserve(nodes.size(), springs.size());
    system.resize(nodes.size());
    system.assemble(model, 1e-3, {nodes, nodes, springs});
    // A CG iteration's vectors: the direction y, the product out, the iterate, the residual and the
    // preconditioned residual.
    physics::kernels::Field y, out, iterate, residual, preconditioned;
    for (auto* field : {&y, &out, &iterate, &residual, &preconditioned}) field->resize(system.rows());
    for (std::size_t k = 0; k < nodes.size(); ++k)
        y.x[k] = std::sin(0.1 * static_cast<double>(k)), y.y[k] = 1, y.z[k] = std::cos(0.3 * static_cast<double>(k));
    residual = system.rhs();

    // The springs stretched, squeezed and moving, as in a step.
    std::vector<Vec3> x = model.nodes.position, v(x.size());
    physics::ForceRows f(x.size());
    for (std::size_t k = 0; k < x.size(); ++k) {
        const auto t = static_cast<double>(k);
        x[k] += 1e-4 * Vec3(std::sin(t), std::cos(1.3 * t), std::sin(0.7 * t));
        v[k] = 1e-2 * Vec3(std::cos(t), std::sin(2.1 * t), 0.5);
    }

    auto medianOf = [&](auto&& run) {
        std::vector<double> samples;
        const auto end = Clock::now() + std::chrono::duration<double>(seconds);
        while (Clock::now() < end || samples.size() < 20) {
            const auto t0 = Clock::now();
            run();
            samples.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        }
        return summarize(samples).p50;
    };
    std::vector<KernelTiming> timings;
    for (const char* target : physics::kernels::supportedTargets()) {
        physics::kernels::forceTarget(target);
        double sink = 0;
        const double product = medianOf([&] { sink += physics::kernels::multiply(system.matrix(), y, out); });
        // The passes with a small step and a damped direction, so that repeating them keeps every value finite.
        const physics::kernels::RowRange rows{0, system.rows()};
        const double update = medianOf([&] {
            sink += physics::kernels::updatePass(rows, 1e-6, y, out, system.inverseBlocks(), iterate, residual,
                                                 preconditioned)
                        .r2;
        });
        const double direction = medianOf([&] { physics::kernels::directionPass(rows, 0.5, preconditioned, y); });
        const double forces = medianOf([&] { physics::accumulateSpringForces(model.springs, x, v, f); });
        const double assembly = medianOf([&] { system.assemble(model, 1e-3, {nodes, nodes, springs}); });
        const double kept = medianOf([&] { system.assemble(model, 1e-3, {nodes, nodes, springs, 1}); });
        const auto count = static_cast<double>(springs.size());
        timings.push_back({target, product, 1e3 * product / (2.0 * count), update + direction,
                           product + update + direction, forces, 1e3 * forces / count, assembly, 1e3 * assembly / count,
                           kept, 1e3 * kept / count});
        if (sink == 42 || !std::isfinite(f[0].x))
            timings.back().target += "";  // keeps the work from being optimised away
    }
    physics::kernels::forceTarget(nullptr);
    return timings;
}

}  // namespace hapticut::bench
