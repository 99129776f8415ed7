// A headless simulation run: step a model for a while, optionally pressing one node, and measure it.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/common/stats.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/mass_spring_model.h"
#include "hapticut/physics/solver_stats.h"

namespace hapticut::scene {

struct PointForce {
    Vec3 at_m = Vec3::Zero();  // the force goes to the node nearest this point
    Vec3 force_N = Vec3::Zero();
    double until_s = 1e300;  // released at this simulated time
};

struct RunConfig {
    physics::Scheme scheme = physics::Scheme::Auto;
    physics::SolverSettings solver{};
    double dt_s = 1e-3;
    long steps = 1000;
    std::optional<PointForce> force;
    /// Asked every few steps; true ends the run early (Ctrl-C). RunResult::steps says how far it got.
    std::function<bool()> stopRequested;
};

struct RunResult {
    long steps = 0;  // done: fewer than asked when stopped early
    bool stoppedEarly = false;
    double simTime_s = 0, wallTime_s = 0;
    Summary step_us;                                        // wall time per step (a histogram: any run length)
    physics::Scheme scheme = physics::Scheme::RungeKutta4;  // the one used (Auto resolved)
    int substeps = 1;                                       // per step, chosen for stability
    physics::SolverStats solver;                            // the implicit scheme's solves
    double stableStep_s = 0;
    double maxDisplacement_m = 0, finalMaxDisplacement_m = 0;
    double kineticEnergyEnd_J = 0;
    long nanEvents = 0;
    // Only with a force:
    std::uint32_t forceNode = 0;
    double forceNodeDisplacementAtRelease_m = 0;  // |x - rest| of the pressed node when released (or at the end)
    double forceNodeDisplacementEnd_m = 0;
    /// Time from release until every node is back within kRecoveredDistance_m of rest; negative if never.
    double recoveryTime_s = -1;
};

inline constexpr double kRecoveredDistance_m = 1e-4;

/// Index of the node whose rest position is nearest `point`.
std::uint32_t nearestNode(const physics::MassSpringModel& model, const Vec3& point);

/// Runs the model in memory independent of the step count; `progress(done, total)` is called about a
/// hundred times, if given, and `slow(what)` once if the run looks like taking more than a minute. An
/// error, before any step, when an explicit scheme would need more than kMaxSubsteps substeps a step.
Result<RunResult, Error> runHeadless(physics::MassSpringModel& model, const RunConfig& config,
                                     const std::function<void(long, long)>& progress = {},
                                     const std::function<void(const std::string&)>& slow = {});

}  // namespace hapticut::scene
