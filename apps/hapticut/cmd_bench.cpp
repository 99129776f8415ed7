// `hapticut bench`: integrator step cost on the procedural heart at several sizes.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <random>

#include "commands.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"
#include "terminal.h"

namespace hapticut::app {

namespace {

struct BenchOptions {
    std::vector<int> triangles = {1619, 9714, 100000};
    std::vector<std::string> integrators = {"euler", "midpoint", "rk4", "symplectic"};
    double seconds = 0.5;
    std::string json;
};

int forceEvaluations(physics::Scheme s) {
    switch (s) {
        case physics::Scheme::Midpoint: return 2;
        case physics::Scheme::RungeKutta4: return 4;
        default: return 1;
    }
}

/// Small random displacements, so that the snap-back rule never short-cuts the work being timed.
void perturb(physics::MassSpringModel& model, std::mt19937& rng) {
    std::normal_distribution<double> noise(0.0, 2e-4);
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
        model.nodes.position[i] = model.nodes.restPosition[i] + Vec3(noise(rng), noise(rng), noise(rng));
        model.nodes.velocity[i] = Vec3::Zero();
    }
}

int bench(const BenchOptions& o) {
    using Clock = std::chrono::steady_clock;
    std::vector<physics::Scheme> schemes;
    for (const std::string& name : o.integrators) {
        const auto s = physics::parseScheme(name);
        if (!s) {
            std::cerr << "hapticut bench: unknown integrator '" << name << "': expected euler, midpoint, rk4 or symplectic\n";
            return 2;
        }
        schemes.push_back(*s);
    }
    nlohmann::ordered_json results = nlohmann::ordered_json::array();
    std::printf("%10s %8s %9s %-11s %11s %11s %13s %9s %15s\n", "triangles", "nodes", "springs", "integrator", "us/step", "p99 us",
                "ns/spring-ev", "substeps", "us/sim-ms@1ms");
    std::mt19937 rng(42);
    for (int triangles : o.triangles) {
        const auto g0 = Clock::now();
        mesh::procedural::HeartOptions heart;
        heart.triangles = triangles;
        const mesh::SurfaceMesh mesh = mesh::procedural::makeHeart(heart);
        const double generate_s = std::chrono::duration<double>(Clock::now() - g0).count();
        physics::MassSpringModel model = physics::buildModel(mesh, physics::Material{});
        for (physics::Scheme scheme : schemes) {
            physics::Stepper stepper(scheme);
            stepper.setAutoSubstep(false);  // time one raw step; substeps are reported separately
            stepper.prepare(model);
            const double stable_s = stepper.stableStep_s();
            const int substeps = std::max(1, static_cast<int>(std::ceil(1e-3 / stable_s)));
            const double h = std::min(1e-3, stable_s);
            std::vector<double> samples;
            const auto end = Clock::now() + std::chrono::duration<double>(o.seconds);
            while (Clock::now() < end || samples.size() < 20) {
                perturb(model, rng);
                for (int i = 0; i < 50; ++i) {
                    const auto t0 = Clock::now();
                    (void)stepper.step(model, h);
                    samples.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
                }
            }
            const Summary s = summarize(samples);
            const double nsPerSpring = 1e3 * s.p50 / (static_cast<double>(model.springs.size()) * forceEvaluations(scheme));
            std::printf("%10zu %8zu %9zu %-11s %11.1f %11.1f %13.2f %9d %15.1f\n", mesh.faces.size(), model.nodes.size(),
                        model.springs.size(), std::string(physics::schemeName(scheme)).c_str(), s.p50, s.p99, nsPerSpring, substeps,
                        s.p50 * substeps);
            results.push_back({{"triangles", mesh.faces.size()},
                               {"nodes", model.nodes.size()},
                               {"springs", model.springs.size()},
                               {"integrator", physics::schemeName(scheme)},
                               {"step_us", toJson(s)},
                               {"ns_per_spring_evaluation", nsPerSpring},
                               {"stable_dt_s", stable_s},
                               {"substeps_at_1ms", substeps},
                               {"us_per_simulated_ms", s.p50 * substeps},
                               {"heart_generation_s", generate_s}});
        }
    }
    if (!o.json.empty()) {
        nlohmann::ordered_json j;
        j["benchmark"] = "integrator step on the procedural heart, one thread";
        j["results"] = results;
        if (!writeJson(o.json, j)) return 1;
        std::cout << "wrote " << o.json << "\n";
    }
    return 0;
}

}  // namespace

Command addBenchCommand(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* cmd = app.add_subcommand("bench", "Measure integrator step time on the procedural heart");
    cmd->add_option("--triangles", o->triangles, "Heart sizes (comma separated)")->delimiter(',')->capture_default_str();
    cmd->add_option("--integrators", o->integrators, "Integrators (comma separated)")->delimiter(',')->capture_default_str();
    cmd->add_option("--seconds", o->seconds, "Minimum timing per case (s)")->capture_default_str()->check(CLI::Range(0.01, 600.0));
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    return [o] { return bench(*o); };
}

}  // namespace hapticut::app
