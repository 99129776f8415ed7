// `hapticut assess`: a recorded session of a scene's exercise replayed headless and scored, with a
// score card on the terminal, a JSON report and a PNG (drawn by the package's Python: hapticut plot).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "hapticut/common/output_path.h"
#include "hapticut/scene/assessment.h"
#include "hapticut/scene/assessment_report.h"
#include "provenance.h"
#include "terminal.h"

namespace hapticut::app {

namespace {

struct AssessOptions {
    std::string scene, session, report, png;
};

void printScoreCard(const scene::Assessment& a, std::ostream& out) {
    const bool incision = a.exercise.kind == scene::SceneExercise::Kind::Incision;
    char line[200];
    std::snprintf(line, sizeof line, "%s: score %.0f of 100\n", incision ? "incision" : "palpation", a.score);
    out << line;
    for (const scene::ScorePart& p : a.parts) {
        std::snprintf(line, sizeof line, "  %-22s %9.2f  (against %.2f)  %5.1f of %2.0f\n", p.metric.c_str(), p.value,
                      p.threshold, p.points, p.weight);
        out << line;
    }
    if (incision)
        std::snprintf(line, sizeof line,
                      "  %ld strokes, %.1f mm cut, deviation max %.2f mm; mean force %.2f N; %.1f s\n", a.strokes,
                      a.cutLength_mm, a.deviationMax_mm, a.meanForce_N, a.duration_s);
    else
        std::snprintf(line, sizeof line, "  %zu marks, %ld of %zu lumps found; mean force %.2f N; %.1f s\n",
                      a.marks.size(), a.found, a.lumps.size(), a.meanForce_N, a.duration_s);
    out << line;
    if (a.timeLimitReached)
        out << "  the session went on past the exercise's " << a.exercise.timeLimit_s
            << " s: what came after was not scored\n";
}

int assess(const AssessOptions& o) {
    for (const std::string& output : {o.report, o.png})
        if (const Status unwritable = checkOutputPath(output)) {
            std::cerr << "hapticut assess: " << unwritable->toString() << "\n";
            return 2;
        }
    scene::SceneRequest request;
    request.file = o.scene;
    const auto scene = app::loadScene(request);
    if (!scene) return 1;
    if (!scene->settings.exercise) {
        std::cerr << "hapticut assess: " << o.scene << ": the scene has no [exercise] (docs/exercises.md)\n";
        return 2;
    }
    const auto session = haptics::readTrajectory(o.session);
    if (!session) {
        std::cerr << "hapticut assess: " << session.error().toString() << "\n";
        return 1;
    }
    std::cerr << "hapticut assess: replaying " << o.session << " (" << session->duration_s() << " s) on "
              << scene->source.name << "\n";
    const auto a = scene::assess(*scene, *session, o.session);
    if (!a) {
        std::cerr << "hapticut assess: " << a.error().toString() << "\n";
        return 1;
    }
    printScoreCard(*a, std::cout);
    // The picture is drawn from the report, which goes beside the PNG when no other was asked for.
    std::string report = o.report;
    if (report.empty() && !o.png.empty()) report = std::filesystem::path(o.png).replace_extension(".json").string();
    if (!report.empty()) {
        nlohmann::ordered_json j;
        j["provenance"] = provenance();
        const nlohmann::ordered_json body = scene::assessmentReport(*a, o.scene, o.session);
        for (const auto& [key, value] : body.items()) j[key] = value;
        if (!writeJson(report, j)) return 1;
        std::cout << "wrote the report to " << report << "\n";
    }
    if (!o.png.empty()) {
        std::cout.flush();
        const int drawn = runPythonCommand("plot", {report, "--out", o.png}, PythonProcess::Wait);
        if (drawn != 0) return drawn;
    }
    return 0;
}

}  // namespace

Command addAssessCommand(CLI::App& app) {
    auto o = std::make_shared<AssessOptions>();
    CLI::App* cmd = app.add_subcommand(
        "assess", "Score a recorded session of a scene's exercise: replayed headless, the same every time");
    cmd->add_option("--scene", o->scene, "The scene with the [exercise]")->required();
    cmd->add_option("--session", o->session,
                    "The session: a recording of hapticut view --record, or any trajectory (CSV)")
        ->required();
    cmd->add_option("--report", o->report, "Write the assessment as JSON");
    cmd->add_option("--png", o->png,
                    "Draw the organ with the target and the cut (or the marks and the lumps) and the force over "
                    "time; the report goes beside it unless --report says where");
    return [o] { return assess(*o); };
}

}  // namespace hapticut::app
