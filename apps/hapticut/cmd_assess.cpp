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
#include "provenance.h"
#include "terminal.h"

namespace hapticut::app {

namespace {

struct AssessOptions {
    std::string scene, session, report, png;
};

nlohmann::ordered_json pointJson(const Vec3& p) { return {p.x(), p.y(), p.z()}; }

nlohmann::ordered_json lineJson(const std::vector<Vec3>& line) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const Vec3& p : line) out.push_back(pointJson(p));
    return out;
}

/// A number, or null for what was not measured.
nlohmann::ordered_json orNull(const std::optional<double>& v) { return v ? nlohmann::ordered_json(*v) : nullptr; }

nlohmann::ordered_json reportOf(const scene::Assessment& a, const AssessOptions& o) {
    const scene::SceneExercise& e = a.exercise;
    const bool incision = e.kind == scene::SceneExercise::Kind::Incision;
    nlohmann::ordered_json j;
    j["provenance"] = provenance();
    j["scene"] = std::filesystem::absolute(o.scene).string();
    j["session"] = std::filesystem::absolute(o.session).string();
    nlohmann::ordered_json& x = j["exercise"];
    x["kind"] = incision ? "incision" : "palpation";
    x["instructions"] = e.instructions;
    x["time_limit_s"] = e.timeLimit_s;
    x["max_force_N"] = e.maxForce_N;
    if (incision) {
        x["corridor_mm"] = 1e3 * e.corridor_m;
        x["depth_mm"] = 1e3 * e.depth_m;
        x["target_length_mm"] = a.targetLength_mm;
    } else {
        x["radius_mm"] = 1e3 * e.radius_m;
        x["lumps"] = a.lumps.size();
    }
    j["score"] = a.score;
    nlohmann::ordered_json& parts = j["parts"];
    parts = nlohmann::ordered_json::array();
    for (const scene::ScorePart& p : a.parts)
        parts.push_back({{"metric", p.metric},
                         {"value", p.value},
                         {"threshold", p.threshold},
                         {"weight", p.weight},
                         {"points", p.points},
                         {"rule", p.rule}});
    if (incision) {
        j["deviation_rms_mm"] = a.deviationRms_mm;
        j["deviation_max_mm"] = a.deviationMax_mm;
        j["coverage_pct"] = a.coverage_pct;
        j["outside_corridor_mm"] = a.outsideCorridor_mm;
        j["cut_length_mm"] = a.cutLength_mm;
        j["depth_mean_mm"] = a.depthMean_mm;
        j["depth_max_mm"] = a.depthMax_mm;
        j["strokes"] = a.strokes;
    } else {
        j["found"] = a.found;
        j["localisation_error_mm"] = orNull(a.localisationError_mm);
        j["marks"] = a.marks.size();
    }
    j["max_force_N"] = a.maxForce_N;
    j["mean_force_N"] = a.meanForce_N;
    j["duration_s"] = a.duration_s;
    j["session_s"] = a.session_s;
    j["time_limit_reached"] = a.timeLimitReached;
    j["steps"] = a.run.steps;
    j["invariants_ok"] = a.run.invariantProblems.empty();
    // What the picture is drawn from: lines and points on the rest surface, and the force over time
    // (at most 4,000 samples: the largest force of each stretch, so no peak is lost).
    nlohmann::ordered_json& f = j["figure"];
    if (incision) {
        f["target_m"] = lineJson(a.target_m);
        f["cuts_m"] = nlohmann::ordered_json::array();
        for (const std::vector<Vec3>& cut : a.cuts_m) f["cuts_m"].push_back(lineJson(cut));
    } else {
        f["marks"] = nlohmann::ordered_json::array();
        for (const scene::Assessment::Mark& m : a.marks)
            f["marks"].push_back({{"t_s", m.t_s}, {"at_m", pointJson(m.at_m)}, {"lump", m.lump}});
        f["lumps"] = nlohmann::ordered_json::array();
        for (const scene::Assessment::Lump& l : a.lumps)
            f["lumps"].push_back({{"center_m", pointJson(l.center_m)},
                                  {"surface_m", pointJson(l.surface_m)},
                                  {"found", l.found},
                                  {"error_mm", orNull(l.error_mm)}});
    }
    const std::size_t n = a.force_N.size(), stride = std::max<std::size_t>(1, (n + 3999) / 4000);
    nlohmann::ordered_json t = nlohmann::ordered_json::array(), force = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < n; i += stride) {
        const std::size_t end = std::min(n, i + stride);
        t.push_back(a.forceTime_s[i]);
        force.push_back(
            *std::max_element(a.force_N.begin() + static_cast<long>(i), a.force_N.begin() + static_cast<long>(end)));
    }
    f["force_t_s"] = std::move(t);
    f["force_N"] = std::move(force);
    return j;
}

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
        if (!writeJson(report, reportOf(*a, o))) return 1;
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
