// `hapticut soak`: the cutting fuzz for as long as asked, with progress and a JSON report.
#include <CLI/CLI.hpp>

#include <iostream>

#include "commands.h"
#include "hapticut/common/output_path.h"
#include "hapticut/common/stop_signal.h"
#include "hapticut/cutting/stroke_fuzzer.h"
#include "hapticut/scene/scene.h"
#include "provenance.h"
#include "terminal.h"
#include "unit_options.h"

namespace hapticut::app {

namespace {

struct SoakOptions {
    std::string model = "heart", report;
    int triangles = 1619;
    UnitOptions units;
    cutting::StrokeFuzzConfig fuzz;
    bool checkEveryStroke = false;
};

int soak(SoakOptions& o) {
    if (const Status unwritable = checkOutputPath(o.report)) {
        std::cerr << "hapticut soak: " << unwritable->toString() << "\n";
        return 2;
    }
    scene::SceneRequest request;
    request.overrides.model = o.model;
    request.overrides.triangles = o.triangles;
    o.units.applyTo(request.overrides);
    const auto scene = app::loadScene(request);
    if (!scene) return 1;
    const scene::ModelSource* source = &scene->source;
    o.fuzz.checkEveryOperation = !o.checkEveryStroke;
    std::cerr << "hapticut soak: " << o.fuzz.strokes << " random scalpel strokes on " << source->name << " ("
              << source->mesh.faces.size() << " faces), seed " << o.fuzz.seed << ", a fresh organ every "
              << o.fuzz.strokesPerOrgan << ", invariants after every "
              << (o.fuzz.checkEveryOperation ? "operation" : "stroke") << "\n";
    const StopSignal stopSignal;
    o.fuzz.stopRequested = [] { return StopSignal::requested(); };
    Progress progress("cutting");
    const cutting::StrokeFuzzResult r =
        cutting::fuzzStrokes(source->mesh, o.fuzz, [&](long done, long total) { progress.update(done, total); });
    progress.finish();
    if (r.stoppedEarly)
        std::cerr << "hapticut soak: stopped by signal " << StopSignal::signalNumber() << " after " << r.strokes
                  << " of " << o.fuzz.strokes << " strokes\n";
    std::cout << r.strokes << " strokes on " << r.organs << " organs in " << r.wallTime_s << " s: " << r.operations
              << " operations, " << r.meshChanges << " changed the mesh; " << r.cutPoints << " cut points, "
              << r.verticesAdded << " vertices and " << r.facesAdded << " faces added (largest organ " << r.largestFaces
              << " faces), " << r.wallsClosed << " openings closed with walls, " << r.woundsCrossed
              << " earlier wounds cut through, " << r.joins << " joins"
              << (r.closedOrgan ? ", the organ closed throughout" : "") << "; " << r.invariantChecks
              << " invariant checks: " << (r.ok() ? "all held" : r.problems.front()) << "\n"
              << "cuts that changed the mesh took " << r.cutAt_us.p50 << " us p50, " << r.cutAt_us.p99 << " us p99, "
              << r.cutAt_us.max << " us max\n";
    if (!o.report.empty()) {
        nlohmann::ordered_json j;
        j["provenance"] = provenance();
        j["model"] = source->name;
        j["faces"] = source->mesh.faces.size();
        j["seed"] = o.fuzz.seed;
        j["strokes"] = r.strokes;
        j["strokes_requested"] = o.fuzz.strokes;
        j["stopped_by_signal"] = r.stoppedEarly;
        j["organs"] = r.organs;
        j["operations"] = r.operations;
        j["mesh_changes"] = r.meshChanges;
        j["invariant_checks"] = r.invariantChecks;
        j["cut_points"] = r.cutPoints;
        j["vertices_added"] = r.verticesAdded;
        j["faces_added"] = r.facesAdded;
        j["joins"] = r.joins;
        j["walls_closed"] = r.wallsClosed;
        j["wounds_crossed"] = r.woundsCrossed;
        j["cut_us"] = toJson(r.cutAt_us);
        j["closed_organ"] = r.closedOrgan;
        j["largest_faces"] = r.largestFaces;
        j["opened"] = r.opened;
        j["invariants_ok"] = r.ok();
        j["problems"] = r.problems;
        j["wall_time_s"] = r.wallTime_s;
        if (!writeJson(o.report, j)) return 1;
        std::cout << "wrote the report to " << o.report << "\n";
    }
    return !r.ok() ? 3 : r.stoppedEarly ? 128 + StopSignal::signalNumber() : 0;
}

}  // namespace

Command addSoakCommand(CLI::App& app) {
    auto o = std::make_shared<SoakOptions>();
    CLI::App* cmd = app.add_subcommand(
        "soak", "Cut a model with random scalpel strokes, checking every cutting invariant as it goes");
    cmd->add_option("--model", o->model, "'heart' or a model file")->capture_default_str();
    addUnitOptions(cmd, o->units);
    cmd->add_option("--triangles", o->triangles, "Triangle count of the procedural heart")
        ->capture_default_str()
        ->check(CLI::Range(12, 20'000'000));
    cmd->add_option("--strokes", o->fuzz.strokes, "How many strokes")
        ->capture_default_str()
        ->check(CLI::Range(1L, 1'000'000'000L));
    cmd->add_option("--seed", o->fuzz.seed, "Random seed (a failure names the seed that replays it)")
        ->capture_default_str();
    cmd->add_option("--per-organ", o->fuzz.strokesPerOrgan, "Strokes before a fresh organ")
        ->capture_default_str()
        ->check(CLI::Range(1L, 1'000'000L));
    cmd->add_flag("--check-every-stroke", o->checkEveryStroke,
                  "Check the invariants after every stroke instead of every operation (faster)");
    cmd->add_option("--report", o->report, "Write a JSON report");
    return [o] { return soak(*o); };
}

}  // namespace hapticut::app
