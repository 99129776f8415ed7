// Terminal helpers: a progress line for long runs, vector and size arguments, JSON files.
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "hapticut/common/stats.h"
#include "hapticut/geometry/vec.h"
#include "hapticut/physics/solver_stats.h"
#include "hapticut/scene/run_report.h"
#include "hapticut/scene/scene.h"

namespace hapticut::app {

/// Progress on stderr with the time taken and the time left: on a terminal one line redrawn in place
/// (five times a second at most); into a file or a pipe (a log, CI, nohup), from 5 s on, a line for each
/// tenth done and at least one every 30 s, so a long run's log shows it alive and how far it got.
class Progress {
public:
    explicit Progress(std::string label);
    /// `total` <= 0: no end known (a live run); the count and the time taken.
    void update(long done, long total);
    void finish();

private:
    using Clock = std::chrono::steady_clock;
    std::string label_;
    bool terminal_;
    Clock::time_point start_ = Clock::now(), lastLine_ = start_;
    long lastTenth_ = 0;
    bool drawn_ = false;
};

/// Parses "X,Y,Z" (locale-independent); empty on anything else.
std::optional<Vec3> parseVec3(const std::string& text);

/// Parses "WIDTHxHEIGHT" with both within [min, max]; empty on anything else.
std::optional<std::pair<int, int>> parseSize(const std::string& text, int min, int max);

using scene::solverJson;  // scene/run_report.h
using scene::toJson;
/// "; implicit: N CG iterations p50, ... " for a run's summary line; empty for an explicit scheme.
std::string solverLine(physics::Scheme scheme, const physics::SolverStats& stats);

/// The model (`heart` or a file), with its warnings printed; on failure prints "file:line: message" and
/// returns nothing.
std::optional<scene::ModelSource> loadModelSource(const std::string& model, int triangles,
                                                  std::span<const std::string> parts = {});
/// The scene, with its model's warnings printed; on failure prints "file:line: message" and returns nothing.
std::optional<scene::Scene> loadScene(const scene::SceneRequest& request);
/// The same, for settings already read (scene::assembleScene).
std::optional<scene::Scene> assembleScene(const std::filesystem::path& file, scene::SceneFile settings);

/// Writes JSON (indented) through a temporary file; prints the error and returns false on failure.
bool writeJson(const std::filesystem::path& file, const nlohmann::ordered_json& json);

}  // namespace hapticut::app
