// Google Benchmark: spring forces and integrator steps on the procedural heart at several sizes.
#include <benchmark/benchmark.h>

#include <map>
#include <random>

#include "hapticut/geometry/random_vec.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/backward_euler_system.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/spring_forces.h"
#include "hapticut/scene/bench_scenes.h"

namespace {

using namespace hapticut;

/// Hearts are cached per size: generating the large ones takes seconds.
const physics::MassSpringModel& heartModel(int triangles) {
    static std::map<int, physics::MassSpringModel> cache;
    auto it = cache.find(triangles);
    if (it == cache.end()) {
        it = cache.emplace(triangles, scene::benchHeart(triangles).buildModel()).first;
        auto& m = it->second;
        for (std::size_t i = 0; i < m.nodes.size(); ++i) {
            const auto x = static_cast<double>(i);  // a fixed irregular offset, so no spring sits at rest
            m.nodes.position[i] += Vec3(1e-4 * std::sin(1.3 * x), 1e-4 * std::cos(0.7 * x), 0.0);
        }
    }
    return it->second;
}

void BM_SpringForces(benchmark::State& state) {
    physics::MassSpringModel model = heartModel(static_cast<int>(state.range(0)));
    physics::ForceRows f(model.nodes.size());
    for (auto _ : state) {
        std::fill(f.begin(), f.end(), physics::ForceRow{});
        physics::accumulateSpringForces(model.springs, model.nodes.position, model.nodes.velocity, f);
        benchmark::DoNotOptimize(f.data());
    }
    state.counters["springs"] = static_cast<double>(model.springs.size());
    state.counters["ns_per_spring"] =
        benchmark::Counter(static_cast<double>(model.springs.size()),
                           benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SpringForces)->Arg(1619)->Arg(9714)->Arg(100'000)->Unit(benchmark::kMicrosecond);

template <physics::Scheme kScheme>
void BM_Step(benchmark::State& state) {
    physics::MassSpringModel model = heartModel(static_cast<int>(state.range(0)));
    physics::Stepper stepper(kScheme);
    stepper.setAutoSubstep(false);  // one raw step; the stable step is reported as a counter
    stepper.prepare(model);
    const double dt = std::min(1e-3, stepper.stableStep_s());
    for (auto _ : state) benchmark::DoNotOptimize(stepper.step(model, dt));
    state.counters["substeps_at_1ms"] = std::ceil(1e-3 / stepper.stableStep_s());
}
BENCHMARK(BM_Step<physics::Scheme::ExplicitEuler>)->Arg(1619)->Arg(9714)->Arg(100'000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step<physics::Scheme::Midpoint>)->Arg(1619)->Arg(9714)->Arg(100'000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step<physics::Scheme::RungeKutta4>)->Arg(1619)->Arg(9714)->Arg(100'000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step<physics::Scheme::SymplecticEuler>)->Arg(1619)->Arg(9714)->Arg(100'000)->Unit(benchmark::kMicrosecond);

/// Each step taken whole (no substeps) and solved on one thread, as `bench --threads 1` measures it.
void takeWholeStepsOnOneThread(physics::Stepper& stepper) {
    stepper.setAutoSubstep(false);
    physics::SolverSettings settings = stepper.solverSettings();
    settings.threads = 1;
    stepper.setSolverSettings(settings);
}

/// The implicit steps of the whole heart at 1 ms on one thread after it is let go from small random
/// displacements, as `hapticut bench` times them: one iteration is 50 steps, the first few with many CG
/// iterations and Newton corrections, then settling ones with a few CG iterations.
void BM_ImplicitSteps(benchmark::State& state) {
    constexpr int kSteps = 50;
    physics::MassSpringModel model = heartModel(static_cast<int>(state.range(0)));
    physics::Stepper stepper(physics::Scheme::BackwardEuler);
    takeWholeStepsOnOneThread(stepper);
    stepper.prepare(model);
    std::mt19937 rng(42);
    std::normal_distribution<double> noise(0.0, 2e-4);
    for (auto _ : state) {
        state.PauseTiming();
        for (std::size_t i = 0; i < model.nodes.size(); ++i) {
            model.nodes.position[i] = model.nodes.restPosition[i] + randomVec3(noise, rng);
            model.nodes.velocity[i] = Vec3::Zero();
        }
        state.ResumeTiming();
        for (int i = 0; i < kSteps; ++i) benchmark::DoNotOptimize(stepper.step(model, 1e-3));
    }
    state.counters["per_step"] =
        benchmark::Counter(kSteps, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ImplicitSteps)->Arg(9714)->Arg(100'000)->Unit(benchmark::kMillisecond);

/// A press held on the front of the heart, integrated as the haptic loop integrates it: implicitly, over
/// the active region only (the nodes the press keeps off rest and their neighbours), once the press has
/// settled. The step a user's organ costs while it is touched, where BM_ImplicitSteps wakes it all.
void BM_ImplicitHeldPress(benchmark::State& state) {
    physics::MassSpringModel model = scene::benchHeart(static_cast<int>(state.range(0))).buildModel();
    physics::Stepper stepper(physics::Scheme::BackwardEuler);
    takeWholeStepsOnOneThread(stepper);
    stepper.setActiveRegion(true);
    stepper.prepare(model);
    std::uint32_t front = 0;  // the node farthest along +z, where the shipped trajectories press
    for (std::uint32_t i = 0; i < model.nodes.size(); ++i)
        if (model.nodes.restPosition[i].z() > model.nodes.restPosition[front].z()) front = i;
    model.nodes.externalForce[front] = Vec3(0, 0, -1);  // 1 N into the heart
    stepper.wake(front);
    for (int i = 0; i < 500; ++i) stepper.step(model, 1e-3);  // the press settles: 0.5 s
    for (auto _ : state) benchmark::DoNotOptimize(stepper.step(model, 1e-3));
    state.counters["awake_nodes"] = static_cast<double>(stepper.awakeCount());
}
BENCHMARK(BM_ImplicitHeldPress)->Arg(9714)->Arg(100'000)->Unit(benchmark::kMicrosecond);

/// The implicit step's assembly alone (matrix, right-hand side and preconditioner) of the whole heart
/// at a 1 ms step, the heart moving: a fixed cost of every implicit step and Newton correction. The
/// second argument: 1 assembles over the last step's layout, as the steps of an unchanged region do.
void BM_ImplicitAssemble(benchmark::State& state) {
    physics::MassSpringModel model = heartModel(static_cast<int>(state.range(0)));
    for (std::size_t i = 0; i < model.nodes.size(); ++i) model.nodes.velocity[i] = Vec3(1e-2, 0, 0);
    std::vector<std::uint32_t> nodes(model.nodes.size()), springs(model.springs.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i] = static_cast<std::uint32_t>(i);
    for (std::size_t e = 0; e < springs.size(); ++e) springs[e] = static_cast<std::uint32_t>(e);
    physics::BackwardEulerSystem system;
    system.reserve(nodes.size(), springs.size());
    system.resize(nodes.size());
    const physics::SolveRegion region{nodes, nodes, springs, static_cast<std::uint64_t>(state.range(1))};
    for (auto _ : state) {
        system.assemble(model, 1e-3, region);
        benchmark::DoNotOptimize(system.rhs().x.data());
    }
    state.counters["ns_per_spring"] =
        benchmark::Counter(static_cast<double>(springs.size()),
                           benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ImplicitAssemble)
    ->Args({9714, 0})
    ->Args({9714, 1})
    ->Args({100'000, 0})
    ->Args({100'000, 1})
    ->Unit(benchmark::kMicrosecond);

void BM_MakeHeart(benchmark::State& state) {
    mesh::procedural::HeartOptions options;
    options.triangles = static_cast<int>(state.range(0));
    for (auto _ : state) benchmark::DoNotOptimize(mesh::procedural::makeHeart(options));
}
BENCHMARK(BM_MakeHeart)->Arg(1619)->Arg(9714)->Arg(100'000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
