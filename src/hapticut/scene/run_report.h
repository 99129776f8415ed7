// A haptic run's report as JSON: what `hapticut run --report` writes and hapticut.run() returns, from
// one place so that the two are the same.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hapticut/common/stats.h"
#include "hapticut/cutting/cut_model.h"
#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/physics/solver_stats.h"
#include "hapticut/scene/haptic_run.h"
#include "hapticut/scene/model_source.h"
#include "hapticut/scene/scene.h"

namespace hapticut::scene {

nlohmann::ordered_json toJson(const Summary& s);  // {mean, p50, p99, max}
nlohmann::ordered_json toJson(const Vec3& v);     // [x, y, z]
/// The implicit scheme's solves over a run and the settings they stopped by; null for an explicit scheme.
nlohmann::ordered_json solverJson(physics::Scheme scheme, const physics::SolverStats& stats,
                                  const physics::SolverSettings& settings);

/// One hand of a run, as the report names it.
struct ReportedHand {
    std::string device;       // "replay:press.csv", "openhaptics:Left Touch", ...
    std::string description;  // what the device said of itself when it opened
    std::string tool;
    ToolTip tip;
};

/// What a run was asked to do, beside the organ, the loop's settings and the result.
struct HapticRunRequest {
    physics::Scheme requestedScheme = physics::Scheme::Auto;
    double rate_hz = 1000;
    std::string tool;        // the first hand's
    std::string trajectory;  // the replayed file, or empty
    bool realtime = false;
    long stepsRequested = -1;  // negative: until stopped
    bool stoppedBySignal = false;
    std::vector<ReportedHand> hands;
};

/// The report of a haptic run on `organ` (the model `source` became) with `loop`'s settings, without the
/// provenance that the caller knows (the command line, the build).
nlohmann::ordered_json hapticRunReport(const ModelSource& source, const cutting::CutModel& organ,
                                       const haptics::LoopConfig& loop, const HapticRunRequest& request,
                                       const HapticRunResult& result);

}  // namespace hapticut::scene
