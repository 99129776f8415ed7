// An assessment as JSON: the report `hapticut assess --report` writes and `hapticut.assess` returns.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "hapticut/scene/assessment.h"

namespace hapticut::scene {

/// The score and its parts, the exercise's thresholds, every metric, and what the picture is drawn from
/// (docs/commands.md lists the keys); the caller adds its provenance.
nlohmann::ordered_json assessmentReport(const Assessment& assessment, const std::filesystem::path& sceneFile,
                                        const std::filesystem::path& sessionFile);

}  // namespace hapticut::scene
