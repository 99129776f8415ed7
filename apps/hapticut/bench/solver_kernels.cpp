// Timing the implicit solve's product under each instruction set.
#include "bench/solver_kernels.h"

#include <algorithm>
#include <chrono>
#include <numeric>

#include "hapticut/common/stats.h"
#include "hapticut/physics/backward_euler_system.h"
#include "hapticut/physics/solver_kernels.h"

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
    physics::kernels::Field y, out;
    y.resize(system.rows());
    out.resize(system.rows());
    for (std::size_t k = 0; k < nodes.size(); ++k)
        y.x[k] = std::sin(0.1 * static_cast<double>(k)), y.y[k] = 1, y.z[k] = std::cos(0.3 * static_cast<double>(k));

    std::vector<KernelTiming> timings;
    for (const char* target : physics::kernels::supportedTargets()) {
        physics::kernels::forceTarget(target);
        std::vector<double> samples;
        double sink = 0;
        const auto end = Clock::now() + std::chrono::duration<double>(seconds);
        while (Clock::now() < end || samples.size() < 20) {
            const auto t0 = Clock::now();
            sink += physics::kernels::multiply(system.matrix(), y, out);
            samples.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        }
        const double median = summarize(samples).p50;
        timings.push_back({target, median, 1e3 * median / (2.0 * static_cast<double>(springs.size()))});
        if (sink == 42) timings.back().target += "";  // keeps the products from being optimised away
    }
    physics::kernels::forceTarget(nullptr);
    return timings;
}

}  // namespace hapticut::bench
