// A headless simulation run with per-step timing.
#include "hapticut/scene/headless_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "hapticut/common/latency_histogram.h"
#include "hapticut/common/line_reader.h"
#include "hapticut/physics/stability.h"

namespace hapticut::scene {

std::uint32_t nearestNode(const physics::MassSpringModel& model, const Vec3& point) {
    std::uint32_t best = 0;
    double bestD2 = 1e300;
    for (std::uint32_t i = 0; i < model.nodes.size(); ++i) {
        const double d2 = (model.nodes.restPosition[i] - point).squaredNorm();
        if (d2 < bestD2) bestD2 = d2, best = i;
    }
    return best;
}

Result<RunResult, Error> runHeadless(physics::MassSpringModel& model, const RunConfig& config,
                                     const std::function<void(long, long)>& progress,
                                     const std::function<void(const std::string&)>& slow) {
    using Clock = std::chrono::steady_clock;
    RunResult r;
    r.scheme = physics::resolveScheme(config.scheme, model, config.dt_s);
    physics::Stepper stepper(r.scheme);
    stepper.setSolverSettings(config.solver);
    stepper.prepare(model);
    r.stableStep_s = stepper.stableStep_s();
    r.substeps = stepper.substepsFor(config.dt_s);
    if (const std::string why = physics::tooManySubsteps(r.scheme, r.substeps, r.stableStep_s, config.dt_s);
        !why.empty())
        return unexpected(Error{{}, 0, why});

    LatencyHistogram stepTimes(0.1, 100'000);
    bool released = false;
    if (config.force) r.forceNode = nearestNode(model, config.force->at_m);
    auto nodeDisplacement = [&] {
        return (model.nodes.position[r.forceNode] - model.nodes.restPosition[r.forceNode]).norm();
    };
    const long progressEvery = std::max(1L, config.steps / 100);

    const auto start = Clock::now();
    long i = 0;
    bool warned = false;
    for (; i < config.steps; ++i) {
        if (config.stopRequested && config.stopRequested()) {
            r.stoppedEarly = true;
            break;
        }
        const double t = static_cast<double>(i) * config.dt_s;
        if (config.force) {
            const bool on = t < config.force->until_s;
            if (!on && !released) {
                released = true;
                r.forceNodeDisplacementAtRelease_m = nodeDisplacement();
            }
            model.nodes.externalForce[r.forceNode] = on ? config.force->force_N : Vec3::Zero();
        }
        const auto t0 = Clock::now();
        const physics::StepResult step = stepper.step(model, config.dt_s);
        stepTimes.record(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        if (!step.finite) ++r.nanEvents;
        if (r.scheme == physics::Scheme::BackwardEuler) r.solver.record(step.solve);
        const double displacement = physics::maxDisplacement(model);
        r.maxDisplacement_m = std::max(r.maxDisplacement_m, displacement);
        if (released && r.recoveryTime_s < 0 && displacement < kRecoveredDistance_m)
            r.recoveryTime_s = static_cast<double>(i + 1) * config.dt_s - config.force->until_s;
        if (progress && (i + 1) % progressEvery == 0) progress(i + 1, config.steps);
        // Two seconds in, say what a run that will take more than a minute spends its time on.
        if (slow && !warned && Clock::now() - start > std::chrono::seconds(2)) {
            warned = true;
            const double perStep_s =
                std::chrono::duration<double>(Clock::now() - start).count() / static_cast<double>(i + 1);
            if (perStep_s * static_cast<double>(config.steps) > 60)
                slow("each step takes " + formatDouble(std::round(perStep_s * 1e4) / 10) + " ms (" +
                     (r.scheme == physics::Scheme::BackwardEuler
                          ? std::string("one implicit solve over ") + std::to_string(model.nodes.size()) + " nodes"
                          : std::to_string(r.substeps) + " substeps of " + std::string(physics::schemeName(r.scheme))) +
                     "): the " + std::to_string(config.steps) + " steps will take about " +
                     formatDouble(std::round(perStep_s * static_cast<double>(config.steps) / 6) / 10) + " min");
        }
    }
    r.wallTime_s = std::chrono::duration<double>(Clock::now() - start).count();
    r.steps = i;
    r.simTime_s = static_cast<double>(i) * config.dt_s;
    r.step_us = stepTimes.summary();
    r.finalMaxDisplacement_m = physics::maxDisplacement(model);
    r.kineticEnergyEnd_J = physics::kineticEnergy(model);
    if (config.force) {
        if (!released) r.forceNodeDisplacementAtRelease_m = nodeDisplacement();
        r.forceNodeDisplacementEnd_m = nodeDisplacement();
    }
    return r;
}

}  // namespace hapticut::scene
