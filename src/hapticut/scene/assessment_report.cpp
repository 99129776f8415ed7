// An assessment as JSON: the report `hapticut assess --report` writes and `hapticut.assess` returns.
#include "hapticut/scene/assessment_report.h"

#include <algorithm>

namespace hapticut::scene {

namespace {

nlohmann::ordered_json pointJson(const Vec3& p) { return {p.x(), p.y(), p.z()}; }

nlohmann::ordered_json lineJson(const std::vector<Vec3>& line) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const Vec3& p : line) out.push_back(pointJson(p));
    return out;
}

/// A number, or null for what was not measured.
nlohmann::ordered_json orNull(const std::optional<double>& v) { return v ? nlohmann::ordered_json(*v) : nullptr; }

}  // namespace

nlohmann::ordered_json assessmentReport(const Assessment& a, const std::filesystem::path& sceneFile,
                                        const std::filesystem::path& sessionFile) {
    const SceneExercise& e = a.exercise;
    const bool incision = e.kind == SceneExercise::Kind::Incision;
    nlohmann::ordered_json j;
    j["scene"] = std::filesystem::absolute(sceneFile).string();
    j["session"] = std::filesystem::absolute(sessionFile).string();
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
    for (const ScorePart& p : a.parts)
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
        for (const Assessment::Mark& m : a.marks)
            f["marks"].push_back({{"t_s", m.t_s}, {"at_m", pointJson(m.at_m)}, {"lump", m.lump}});
        f["lumps"] = nlohmann::ordered_json::array();
        for (const Assessment::Lump& l : a.lumps)
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

}  // namespace hapticut::scene
