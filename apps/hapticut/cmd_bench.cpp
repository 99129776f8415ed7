// `hapticut bench`: integrator step cost on the procedural heart at several sizes.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <random>

#include "bench/machine_probes.h"
#include "bench/solver_kernels.h"
#include "commands.h"
#include "hapticut/collision/bvh.h"
#include "hapticut/common/latency_histogram.h"
#include "hapticut/common/output_path.h"
#include "hapticut/common/worker_pool.h"
#include "hapticut/geometry/random_vec.h"
#include "hapticut/haptics/contact_footprint.h"
#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/proxy.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/mesh/vertex_faces.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/solver_kernels.h"
#include "hapticut/scene/bench_scenes.h"
#include "hapticut/scene/model_info.h"
#include "hapticut/scene/sample_trajectories.h"
#include "provenance.h"
#include "terminal.h"
#include "unit_options.h"
#ifdef HAPTICUT_WITH_VIEWER
#include "bench/frame_rate.h"
#endif

namespace hapticut::app {

namespace {

struct BenchOptions {
    std::vector<int> triangles = {1619, 9714, 100000};
    std::string model;  // a model file measured instead of the hearts (the integrators and the kernels)
    UnitOptions units;
    std::vector<std::string> integrators = {"euler", "midpoint", "rk4", "symplectic", "implicit"};
    std::vector<unsigned> threads = {1, WorkerPool::hardwareThreads()};  // the implicit solve's, each measured
    std::vector<std::string> preconditioners = {"auto"};                 // the implicit solve's, each measured
    double seconds = 0.5;
    std::string json;
    bool haptics = false;
    bool render = false;
    bool cutting = false;
    std::vector<std::string> sizes = {"1280x1024", "1600x1200"};
};

/// Cut events through the haptic loop: the scalpel's 12 mm stroke across the front (the shipped
/// cut-front path, generated for this heart) with the physics paused, so the finest hearts' substeps do
/// not make the run take minutes; a cut event (the cut, the tree, the stepper and the proxy) costs the same.
nlohmann::ordered_json benchCutting(const scene::Scene& scene) {
    const mesh::SurfaceMesh& heart = scene.source.mesh;
    collision::Bvh bvh;
    bvh.build({heart.positions, heart.faces});
    const haptics::Trajectory path = scene::strokeTrajectory(heart, bvh, 0.012);
    cutting::CutModel organ = scene.makeOrgan();
    haptics::ReplayDevice device(path);
    haptics::LoopConfig config;
    config.cutThreshold_N = mesh::procedural::kScalpelThreshold_N;
    config.tipRadius_m = mesh::procedural::kScalpelTipRadius_m;
    haptics::HapticLoop loop(organ, device, config);
    loop.commands().push({haptics::LoopCommand::Kind::Pause, 0});
    haptics::runSimulated(loop, std::lround(path.duration_s() * config.rate_hz) + 1);
    const Summary s = loop.stats().cutTime_us.summary();
    const cutting::CutStats& c = loop.cutter().stats();
    std::printf("%10zu %10ld %10ld %10.0f %10.0f %10.0f %10.0f\n", heart.faces.size(), loop.stats().cutEvents,
                c.cutPoints, s.mean, s.p50, s.p99, s.max);
    return {{"triangles", heart.faces.size()},
            {"cut_events", loop.stats().cutEvents},
            {"cut_points", c.cutPoints},
            {"cut_event_us", toJson(s)}};
}

#ifdef HAPTICUT_WITH_VIEWER
/// Frames per second, mono and side-by-side stereo, at each size and heart, with the loop running.
bool benchRender(const BenchOptions& o, nlohmann::ordered_json& out) {
    std::vector<bench::FrameRateCase> cases;
    for (int triangles : o.triangles)
        for (const std::string& size : o.sizes) {
            const auto wh = parseSize(size, 16, 16384);
            if (!wh) {
                std::cerr << "hapticut bench: --sizes takes WIDTHxHEIGHT, each 16 to 16384, found '" << size << "'\n";
                return false;
            }
            for (render::StereoMode mode : {render::StereoMode::Off, render::StereoMode::SideBySide})
                cases.push_back({triangles, wh->first, wh->second, mode});
        }
    std::printf("\n%10s %11s %13s %10s %12s\n", "triangles", "size", "stereo", "fps", "haptic Hz");
    std::vector<bench::FrameRateResult> results;
    std::string renderer, error;
    const bool ok =
        bench::measureFrameRates(cases, o.seconds, results, renderer, error, [](const bench::FrameRateResult& r) {
            std::printf("%10d %5dx%-5d %13s %10.1f %12.0f\n", r.faces, r.what.width, r.what.height,
                        std::string(render::stereoModeName(r.what.stereo)).c_str(), r.fps, r.hapticRate_hz);
            std::fflush(stdout);
        });
    if (!ok) {
        std::cerr << "hapticut bench --render: " << error << "\n";
        return false;
    }
    std::printf("renderer: %s\n", renderer.c_str());
    out["renderer"] = renderer;
    out["results"] = nlohmann::ordered_json::array();
    for (const bench::FrameRateResult& r : results)
        out["results"].push_back({{"triangles", r.faces},
                                  {"width", r.what.width},
                                  {"height", r.what.height},
                                  {"stereo", render::stereoModeName(r.what.stereo)},
                                  {"frames", r.frames},
                                  {"fps", r.fps},
                                  {"haptic_rate_hz", r.hapticRate_hz}});
    return true;
}
#endif

/// BVH build and refit, and the proxy update while it slides in contact over the front of the heart
/// (0.2 mm per update, as at 0.2 m/s and 1 kHz): mean and p99 of each update, timed one by one. Each
/// update is also timed on two copies of the proxy, and the least of the three kept: a gap the machine
/// takes (measureClockGaps) seldom falls in all three, so that figure is the update's own work.
nlohmann::ordered_json benchHaptics(const mesh::SurfaceMesh& mesh, double seconds) {
    using Clock = std::chrono::steady_clock;
    const collision::SurfaceView view{mesh.positions, mesh.faces};
    collision::Bvh bvh;
    bvh.setMargin(haptics::kTreeMarginPerEdge * mesh::meanEdgeLength(mesh));  // the haptic loop's tree
    auto t0 = Clock::now();
    bvh.build(view);
    const double build_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    LatencyHistogram refit(0.1, 200'000), update(0.01, 2'000), updateBest(0.01, 2'000);
    const auto refitEnd = Clock::now() + std::chrono::duration<double>(seconds / 2);
    while (Clock::now() < refitEnd || refit.count() < 5) {
        t0 = Clock::now();
        bvh.refit(view);
        refit.record(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    }
    const mesh::VertexFaces topology = mesh::buildVertexFaces(mesh.faces, mesh.positions.size());
    haptics::GodObjectProxy proxy(haptics::ProxyParams{.closedSurface = true});
    proxy.setTopology(&topology);
    proxy.reset(Vec3(0, 0, 0.2));
    long contacts = 0, step = 0;
    const auto updateEnd = Clock::now() + std::chrono::duration<double>(seconds / 2);
    while (Clock::now() < updateEnd || update.count() < 1000) {
        const Vec3 device = scene::slidingDevice_m(++step);
        double best_us = std::numeric_limits<double>::infinity();
        for (int repeat = 0; repeat < 2; ++repeat) {
            haptics::GodObjectProxy copy = proxy;
            t0 = Clock::now();
            copy.update(device, view, bvh);
            best_us = std::min(best_us, std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        }
        t0 = Clock::now();
        proxy.update(device, view, bvh);
        const double us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
        update.record(us);
        updateBest.record(std::min(best_us, us));
        contacts += proxy.contact().active;
    }
    // Building the probe tip's footprint where the sliding proxy touches (the loop builds one each time
    // a contact has slid a twentieth of the tip).
    haptics::ContactFootprint footprint;
    footprint.fitTo(mesh.positions.size(), mesh.faces.size());
    const std::vector<double> anchors(mesh.positions.size(), 1.0);  // their values do not change the work
    auto tool = std::make_unique<physics::PointSpring>();
    LatencyHistogram build(0.01, 100'000);
    std::uint32_t nodes = 0;
    const auto footprintEnd = Clock::now() + std::chrono::duration<double>(seconds / 2);
    while (Clock::now() < footprintEnd || build.count() < 100) {
        proxy.update(scene::slidingDevice_m(++step), view, bvh);
        if (!proxy.contact().active) continue;
        t0 = Clock::now();
        footprint.spread(view, topology, anchors, proxy.contact().face, proxy.contact().bary,
                         mesh::procedural::kProbeTipRadius_m, *tool);
        build.record(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        nodes = std::max(nodes, tool->count);
    }
    const Summary r = refit.summary(), u = update.summary(), ub = updateBest.summary(), b = build.summary();
    std::printf("%10zu %12.2f %12.1f %12.1f %12.2f %12.2f %12.2f %9.0f%% %12.1f %12.1f %8u\n", mesh.faces.size(),
                build_ms, r.mean, r.p99, u.mean, u.p99, ub.p99,
                100.0 * static_cast<double>(contacts) / static_cast<double>(update.count()), b.mean, b.p99, nodes);
    return {{"triangles", mesh.faces.size()},
            {"bvh_build_ms", build_ms},
            {"bvh_refit_us", toJson(r)},
            {"proxy_update_us", toJson(u)},
            {"proxy_update_best_of_3_us", toJson(ub)},
            {"proxy_contact_fraction", static_cast<double>(contacts) / static_cast<double>(update.count())},
            {"footprint_build_us", toJson(b)},
            {"footprint_nodes", nodes}};
}

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
        model.nodes.position[i] = model.nodes.restPosition[i] + randomVec3(noise, rng);
        model.nodes.velocity[i] = Vec3::Zero();
    }
}

int bench(const BenchOptions& o) {
    using Clock = std::chrono::steady_clock;
    if (const Status unwritable = checkOutputPath(o.json)) {
        std::cerr << "hapticut bench: " << unwritable->toString() << "\n";
        return 2;
    }
    if (!o.model.empty() && (o.haptics || o.cutting || o.render)) {
        std::cerr << "hapticut bench: --haptics, --cutting and --render measure the procedural heart (a path in "
                     "contact with its front); leave them out with --model\n";
        return 2;
    }
    std::vector<physics::Scheme> schemes;
    for (const std::string& name : o.integrators) {
        const auto s = physics::parseScheme(name);
        if (!s) {
            std::cerr << "hapticut bench: unknown integrator '" << name
                      << "': expected auto, euler, midpoint, rk4, symplectic or implicit\n";
            return 2;
        }
        schemes.push_back(*s);
    }
    // The organs measured: --model's, or the procedural heart at each size.
    std::optional<scene::Scene> userModel;
    if (!o.model.empty()) {
        scene::SceneRequest request;
        request.overrides.model = o.model;
        o.units.applyTo(request.overrides);
        auto loaded = scene::loadScene(request);
        if (!loaded) {
            std::cerr << "hapticut bench: " << loaded.error().toString() << "\n";
            return 1;
        }
        userModel = std::move(*loaded);
    }
    std::string targets;
    for (const char* t : physics::kernels::supportedTargets()) targets += std::string(targets.empty() ? "" : ", ") + t;
    std::printf("SIMD: the physics' kernels run with %s (this machine runs: %s)\n\n", physics::kernels::targetName(),
                targets.c_str());
    const std::vector<int> sizes = userModel ? std::vector<int>{0} : o.triangles;
    auto organ = [&](int triangles) { return userModel ? *userModel : scene::benchHeart(triangles); };
    nlohmann::ordered_json results = nlohmann::ordered_json::array();
    std::printf("%10s %8s %9s %-11s %7s %-13s %11s %11s %13s %9s %15s %8s\n", "triangles", "nodes", "springs",
                "integrator", "threads", "precond", "us/step", "p99 us", "ns/spring-ev", "substeps", "us/sim-ms@1ms",
                "CG its");
    std::mt19937 rng(42);
    for (int triangles : sizes) {
        const auto g0 = Clock::now();
        const scene::Scene heart = organ(triangles);
        const mesh::SurfaceMesh& mesh = heart.source.mesh;
        const double generate_s = std::chrono::duration<double>(Clock::now() - g0).count();
        physics::MassSpringModel model = heart.buildModel();
        for (const physics::Scheme requested : schemes) {
            const physics::Scheme scheme = physics::resolveScheme(requested, model, 1e-3);
            // The explicit schemes run on one thread; the implicit solve at each thread count asked for.
            std::vector<unsigned> threadCounts{1};
            if (scheme == physics::Scheme::BackwardEuler) {
                threadCounts.clear();
                for (unsigned t : o.threads) {
                    const unsigned resolved = physics::solverThreads(t);
                    if (std::find(threadCounts.begin(), threadCounts.end(), resolved) == threadCounts.end())
                        threadCounts.push_back(resolved);
                }
            }
            // Each preconditioner asked for (auto's choice is its own, step by step).
            std::vector<physics::Preconditioner> preconditioners{physics::Preconditioner::BlockJacobi};
            if (scheme == physics::Scheme::BackwardEuler) {
                preconditioners.clear();
                for (const std::string& name : o.preconditioners) {
                    const physics::Preconditioner p = *physics::parsePreconditioner(name);
                    if (std::find(preconditioners.begin(), preconditioners.end(), p) == preconditioners.end())
                        preconditioners.push_back(p);
                }
            }
            for (const unsigned threads : threadCounts)
                for (const physics::Preconditioner preconditioner : preconditioners) {
                    physics::Stepper stepper(scheme);
                    stepper.setAutoSubstep(false);  // time one raw step; substeps are reported separately
                    physics::SolverSettings settings = stepper.solverSettings();
                    settings.threads = threads;
                    settings.preconditioner = preconditioner;
                    stepper.setSolverSettings(settings);
                    stepper.prepare(model);
                    const double stable_s = stepper.stableStep_s();
                    const int substeps = std::max(1, static_cast<int>(std::ceil(1e-3 / stable_s)));
                    const double h = std::min(1e-3, stable_s);
                    std::vector<double> samples;
                    physics::SolverStats solver;
                    const auto end = Clock::now() + std::chrono::duration<double>(o.seconds);
                    while (Clock::now() < end || samples.size() < 20) {
                        perturb(model, rng);
                        for (int i = 0; i < 50; ++i) {
                            const auto t0 = Clock::now();
                            const physics::StepResult step = stepper.step(model, h);
                            samples.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
                            if (scheme == physics::Scheme::BackwardEuler) solver.record(step.solve);
                        }
                    }
                    const Summary s = summarize(samples);
                    // A CG iteration is one product with the springs' matrix, about the cost of one force evaluation;
                    // the multilevel cycle adds two more, each iteration and at the start.
                    const double products = 1 + 2 * static_cast<double>(solver.multilevel) /
                                                    static_cast<double>(std::max(1L, solver.solves));
                    const double evaluations = scheme == physics::Scheme::BackwardEuler
                                                   ? 1 + products * (solver.iterations.summary().mean + 1) - 1
                                                   : forceEvaluations(scheme);
                    const double nsPerSpring = 1e3 * s.p50 / (static_cast<double>(model.springs.size()) * evaluations);
                    const std::string preconditionerName =
                        scheme == physics::Scheme::BackwardEuler
                            ? std::string(physics::preconditionerName(preconditioner))
                            : "-";
                    std::printf("%10zu %8zu %9zu %-11s %7u %-13s %11.1f %11.1f %13.2f %9d %15.1f %8.1f\n",
                                mesh.faces.size(), model.nodes.size(), model.springs.size(),
                                std::string(physics::schemeName(scheme)).c_str(), threads, preconditionerName.c_str(),
                                s.p50, s.p99, nsPerSpring, substeps, s.p50 * substeps,
                                solver.iterations.summary().mean);
                    results.push_back({{"triangles", mesh.faces.size()},
                                       {"nodes", model.nodes.size()},
                                       {"springs", model.springs.size()},
                                       {"integrator", physics::schemeName(scheme)},
                                       {"threads", threads},
                                       {"preconditioner", scheme == physics::Scheme::BackwardEuler
                                                              ? nlohmann::ordered_json(preconditionerName)
                                                              : nlohmann::ordered_json(nullptr)},
                                       {"step_us", toJson(s)},
                                       {"ns_per_spring_evaluation", nsPerSpring},
                                       {"stable_dt_s", stable_s},
                                       {"substeps_at_1ms", substeps},
                                       {"us_per_simulated_ms", s.p50 * substeps},
                                       {"solver", solverJson(scheme, solver, stepper.solverSettings())},
                                       {"heart_generation_s", generate_s}});
                }
        }
    }
    std::printf(
        "\n%10s %-8s %12s %16s %12s %13s %12s %12s %12s %12s %12s %12s   (the implicit solve's product, a CG "
        "iteration's two passes and the whole iteration, the springs' forces, the assembly laid out afresh and over "
        "the last step's layout, every instruction set, same run)\n",
        "triangles", "target", "product us", "ns/spring-end", "passes us", "iteration us", "springs us", "ns/spring",
        "assembly us", "ns/spring", "kept us", "ns/spring");
    nlohmann::ordered_json kernelTimes = nlohmann::ordered_json::array();
    for (int triangles : sizes) {
        const scene::Scene measured = organ(triangles);
        const physics::MassSpringModel springs = measured.buildModel();
        const std::size_t faces = measured.source.mesh.faces.size();
        for (const bench::KernelTiming& t : bench::timeSolverKernels(springs, std::min(o.seconds, 0.5))) {
            std::printf("%10zu %-8s %12.1f %16.2f %12.1f %13.1f %12.1f %12.2f %12.1f %12.2f %12.1f %12.2f\n", faces,
                        t.target.c_str(), t.product_us, t.ns_per_coupling, t.cg_passes_us, t.cg_iteration_us,
                        t.spring_forces_us, t.ns_per_spring, t.assembly_us, t.assembly_ns_per_spring,
                        t.kept_layout_assembly_us, t.kept_layout_assembly_ns_per_spring);
            kernelTimes.push_back({{"triangles", faces},
                                   {"target", t.target},
                                   {"product_us", t.product_us},
                                   {"ns_per_spring_end", t.ns_per_coupling},
                                   {"cg_passes_us", t.cg_passes_us},
                                   {"cg_iteration_us", t.cg_iteration_us},
                                   {"spring_forces_us", t.spring_forces_us},
                                   {"ns_per_spring", t.ns_per_spring},
                                   {"assembly_us", t.assembly_us},
                                   {"assembly_ns_per_spring", t.assembly_ns_per_spring},
                                   {"kept_layout_assembly_us", t.kept_layout_assembly_us},
                                   {"kept_layout_assembly_ns_per_spring", t.kept_layout_assembly_ns_per_spring}});
        }
    }
    nlohmann::ordered_json haptics = nlohmann::ordered_json::array(), clockGaps;
    if (o.haptics) {
        // What the machine takes away decides how low a p99 of a few microseconds can be measured here.
        const bench::ClockGaps gaps = bench::measureClockGaps(std::min(o.seconds, 1.0));
        std::printf(
            "\nclock gaps over %.0f us in a busy loop: %.0f a second, median %.1f us, longest %.0f us, %.2f%% "
            "of the time\n",
            bench::ClockGaps::kGap_us, gaps.gaps_per_s, gaps.median_gap_us, gaps.longest_gap_us,
            100 * gaps.stolen_share);
        clockGaps = {{"gap_threshold_us", bench::ClockGaps::kGap_us},
                     {"clock_reads_per_s", gaps.reads_per_s},
                     {"gaps_per_s", gaps.gaps_per_s},
                     {"median_gap_us", gaps.median_gap_us},
                     {"longest_gap_us", gaps.longest_gap_us},
                     {"stolen_share", gaps.stolen_share}};
        std::printf("%10s %12s %12s %12s %12s %12s %12s %10s %12s %12s %8s\n", "triangles", "build ms", "refit us",
                    "refit p99", "proxy us", "proxy p99", "best-3 p99", "contact", "tip us", "tip p99", "tip nodes");
        for (int triangles : o.triangles)
            haptics.push_back(benchHaptics(scene::benchHeart(triangles).source.mesh, o.seconds));
    }
    nlohmann::ordered_json cuts = nlohmann::ordered_json::array(), idleTouches;
    if (o.cutting) {
        // A cut event touches memory nothing else has touched for a while (the edge map, the lists round
        // the vertices it reaches): what that costs on this machine after the thread slept.
        const bench::IdlePageTouches touches = bench::measureIdlePageTouches(64, 1.0, 2000);
        std::printf(
            "\npages written, then left alone while the thread slept %.0f s: first touch p50 %.2f us, p99 %.1f us, "
            "max %.0f us, %.1f%% over %.0f us\n",
            touches.idle_s, touches.p50_us, touches.p99_us, touches.max_us, 100 * touches.slow_share,
            bench::IdlePageTouches::kSlow_us);
        idleTouches = {{"idle_s", touches.idle_s},        {"pages", touches.pages},
                       {"p50_us", touches.p50_us},        {"p99_us", touches.p99_us},
                       {"max_us", touches.max_us},        {"slow_threshold_us", bench::IdlePageTouches::kSlow_us},
                       {"slow_share", touches.slow_share}};
        std::printf("%10s %10s %10s %10s %10s %10s %10s\n", "triangles", "events", "points", "mean us", "p50 us",
                    "p99 us", "max us");
        for (int triangles : o.triangles) cuts.push_back(benchCutting(scene::benchHeart(triangles)));
    }
    nlohmann::ordered_json frameRates;
#ifdef HAPTICUT_WITH_VIEWER
    if (o.render && !benchRender(o, frameRates)) return 1;
#endif
    if (!o.json.empty()) {
        nlohmann::ordered_json j;
        j["provenance"] = provenance();
        j["benchmark"] =
            "integrator step on " + (userModel ? o.model : std::string("the procedural heart")) + ", one thread";
        if (userModel) j["vertex_order"] = scene::vertexOrderJson(userModel->source);
        j["simd_target"] = physics::kernels::targetName();
        j["simd_targets_supported"] = physics::kernels::supportedTargets();
        j["results"] = results;
        j["solver_kernels"] = kernelTimes;
        if (o.haptics) j["haptics"] = haptics, j["clock_gaps"] = clockGaps;
        if (o.cutting) j["cutting"] = cuts, j["idle_page_touches"] = idleTouches;
        if (o.render) j["render"] = frameRates;
        if (!writeJson(o.json, j)) return 1;
        std::cout << "wrote " << o.json << "\n";
    }
    return 0;
}

}  // namespace

Command addBenchCommand(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* cmd = app.add_subcommand("bench", "Measure integrator step time on the procedural heart or a model");
    cmd->add_option("--triangles", o->triangles, "Heart sizes (comma separated)")
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--model", o->model,
                    "Measure the integrators and the kernels on this model file instead of the hearts (as it loads for "
                    "a run: renumbered when its vertices come in no spatial order)");
    addUnitOptions(cmd, o->units);
    cmd->add_option("--integrators", o->integrators, "Integrators (comma separated)")
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--threads", o->threads,
                    "Threads of the implicit solve, each measured (comma separated; 0: the run's default, every core "
                    "but two, here " +
                        std::to_string(physics::automaticSolverThreads()) + ")")
        ->delimiter(',')
        ->capture_default_str()
        ->check(CLI::Range(0u, physics::kMaxSolverThreads));
    cmd->add_option("--preconditioners", o->preconditioners,
                    "Preconditioners of the implicit solve, each measured (comma separated: auto, block-jacobi, "
                    "multilevel)")
        ->delimiter(',')
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "block-jacobi", "multilevel"}));
    cmd->add_option("--seconds", o->seconds, "Minimum timing per case (s)")
        ->capture_default_str()
        ->check(CLI::Range(0.01, 600.0));
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->add_flag("--haptics", o->haptics,
                  "Also measure BVH build and refit, the proxy update (mean, p99, and p99 of the best of three "
                  "runs of each update) and the probe tip's footprint build (mean and p99), and how often this "
                  "machine takes the processor away (clock gaps)");
    cmd->add_flag("--cutting", o->cutting,
                  "Also measure the scalpel's cut events through the haptic loop (mean, p50, p99, max), and "
                  "how long this machine takes to touch memory again after the thread slept");
#ifdef HAPTICUT_WITH_VIEWER
    cmd->add_flag("--render", o->render,
                  "Also measure frames per second, mono and side by side, with the haptic loop running (needs a "
                  "display or Xvfb)");
    cmd->add_option("--sizes", o->sizes, "Image sizes for --render (comma separated)")
        ->delimiter(',')
        ->capture_default_str();
#endif
    return [o] { return bench(*o); };
}

}  // namespace hapticut::app
