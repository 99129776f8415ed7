// A haptic run's report as JSON.
#include "hapticut/scene/run_report.h"

#include <algorithm>
#include <cmath>

#include "hapticut/mesh/mesh_report.h"
#include "hapticut/scene/model_info.h"

namespace hapticut::scene {

nlohmann::ordered_json toJson(const Summary& s) {
    return {{"mean", s.mean}, {"p50", s.p50}, {"p99", s.p99}, {"max", s.max}};
}

nlohmann::ordered_json toJson(const Vec3& v) { return nlohmann::ordered_json::array({v.x(), v.y(), v.z()}); }

nlohmann::ordered_json solverJson(physics::Scheme scheme, const physics::SolverStats& stats,
                                  const physics::SolverSettings& settings) {
    if (scheme != physics::Scheme::BackwardEuler) return nullptr;
    const Summary iterations = stats.iterations.summary();
    return {{"method", "conjugate gradients, warm start"},
            {"preconditioner", physics::preconditionerName(settings.preconditioner)},
            {"multilevel_solves", stats.multilevel},
            {"tolerance", settings.tolerance},
            {"force_tolerance_N", settings.forceTolerance_N},
            {"max_iterations", settings.maxIterations},
            {"threads", physics::solverThreads(settings.threads)},
            {"solves", stats.solves},
            {"iterations",
             {{"mean", iterations.mean}, {"p50", iterations.p50}, {"p99", iterations.p99}, {"max", iterations.max}}},
            {"unconverged_solves", stats.unconverged},
            {"max_newton_iterations", settings.maxNewtonIterations},
            {"steps_with_newton_corrections", stats.corrected},
            {"steps_with_newton_cut_short", stats.cutShort},
            {"most_newton_iterations", stats.maxNewtonIterations},
            {"max_relative_residual", stats.maxRelativeResidual}};
}

nlohmann::ordered_json hapticRunReport(const ModelSource& source, const cutting::CutModel& organ,
                                       const haptics::LoopConfig& loop, const HapticRunRequest& request,
                                       const HapticRunResult& result) {
    const mesh::MeshReport after = mesh::validateMesh(organ.mesh());
    nlohmann::ordered_json j;
    j["model"] = source.name;
    j["vertices"] = organ.mesh().positions.size();
    j["vertex_order"] = vertexOrderJson(source);
    j["faces"] = organ.mesh().faces.size();
    j["springs"] = organ.model().springs.size();
    j["integrator"] = physics::schemeName(result.scheme);
    j["integrator_requested"] = physics::schemeName(request.requestedScheme);
    j["dt"] = 1 / request.rate_hz;
    j["substeps"] = result.substeps;
    j["solver"] = solverJson(result.scheme, result.solver, loop.solver);
    j["steps"] = result.steps;
    j["tool"] = request.tool;
    j["tool_threshold_N"] = std::isfinite(loop.cutThreshold_N) ? nlohmann::ordered_json(loop.cutThreshold_N)
                                                               : nlohmann::ordered_json(nullptr);
    j["coupling_stiffness_N_per_m"] = loop.couplingStiffness_N_per_m;
    j["friction"] = {{"static", loop.proxy.staticFriction}, {"dynamic", loop.proxy.dynamicFriction}};
    j["trajectory"] = request.trajectory;
    j["realtime"] = request.realtime;
    nlohmann::ordered_json handsJson = nlohmann::ordered_json::array();
    for (int h = 0; h < result.handCount && h < static_cast<int>(request.hands.size()); ++h) {
        const auto k = static_cast<std::size_t>(h);
        const ReportedHand& hand = request.hands[k];
        const double threshold = hand.tip.threshold_N;
        handsJson.push_back(
            {{"device", hand.device},
             {"description", hand.description},
             {"tool", hand.tool},
             {"tool_threshold_N", std::isfinite(threshold) && threshold < 1e8 ? nlohmann::ordered_json(threshold)
                                                                              : nlohmann::ordered_json(nullptr)},
             {"tip_radius_m", hand.tip.radius_m},
             {"max_force_N", result.hands[k].maxForce_N},
             {"contact_steps", result.hands[k].contactSteps}});
    }
    j["hands"] = handsJson;
    j["stopped_by_signal"] = request.stoppedBySignal;
    // From the signal to the loop stopped with every device at zero force (before the report is written).
    j["stop_latency_ms"] = result.stopLatency_s >= 0 ? nlohmann::ordered_json(result.stopLatency_s * 1e3)
                                                     : nlohmann::ordered_json(nullptr);
    j["steps_requested"] =
        request.stepsRequested >= 0 ? nlohmann::ordered_json(request.stepsRequested) : nlohmann::ordered_json(nullptr);
    j["log_dropped_steps"] = result.droppedLogSteps;
    j["sim_time_s"] = result.simTime_s;
    j["wall_time_s"] = result.wallTime_s;
    // A rate of the haptic loop only on the wall clock; in simulated time it is how fast the run went.
    j["haptic_rate_hz"] =
        request.realtime ? nlohmann::ordered_json(result.hapticRate_hz) : nlohmann::ordered_json(nullptr);
    j["steps_per_wall_s"] = result.hapticRate_hz;
    j["haptic_thread_scheduling"] =
        request.realtime ? nlohmann::ordered_json(result.hapticScheduling) : nlohmann::ordered_json(nullptr);
    j["multi_rate"] = result.multiRate;
    j["multi_rate_from_s"] =
        result.multiRate ? nlohmann::ordered_json(result.multiRateFrom_s) : nlohmann::ordered_json(nullptr);
    // Auto's switch went on at the haptic rate, the tissue held still, for this many steps.
    j["multi_rate_switch_steps"] = result.multiRateSwitchSteps;
    j["physics_rate_hz"] = result.physicsRate_hz;
    j["physics_realtime_factor"] = result.physicsRealtimeFactor;
    // Slower steps than this simulate only this long and leave the rest, up to this long again, to the steps
    // after them: steps slower still make the tissue fall behind, and the factor above says so.
    j["max_physics_step_s"] =
        result.multiRate ? nlohmann::ordered_json(result.maxPhysicsStep_s) : nlohmann::ordered_json(nullptr);
    j["physics_step_us"] =
        result.physicsStepTime_us.count > 0 ? toJson(result.physicsStepTime_us) : nlohmann::ordered_json(nullptr);
    // Where the factor above falls short of 1, multi-rate: wall time left unsimulated where the tissue was
    // more than twice the longest step behind, and how far it was behind the wall clock when the run ended
    // (about one step: the one in progress, what it owed and the frame not yet taken in).
    j["physics_time_lost_s"] = result.multiRate ? nlohmann::ordered_json(result.physicsTimeLost_s) : nullptr;
    j["physics_lag_at_end_s"] =
        result.multiRate && request.realtime ? nlohmann::ordered_json(result.physicsLagAtEnd_s) : nullptr;
    j["step_us"] = toJson(result.stepTime_us);
    j["period_error_us"] = request.realtime ? toJson(result.periodError_us) : nlohmann::ordered_json(nullptr);
    j["overruns"] = result.overruns;
    j["missed_periods"] = result.missedPeriods;
    j["stalls"] = result.stalls;
    j["contact_steps"] = result.contactSteps;
    j["max_force_N"] = result.maxForce_N;
    j["max_proxy_penetration_m"] = result.maxProxyPenetration_m;
    j["penetration_measured_steps"] = result.penetrationMeasuredSteps;
    j["proxy_push_outs"] = result.proxyPushOuts;
    j["proxy_deepest_push_out_m"] = result.proxyDeepestPushOut_m;
    j["max_displacement_m"] = result.maxDisplacement_m;
    j["final_max_displacement_m"] = result.finalMaxDisplacement_m;
    j["volume_kept"] = result.volumeKept;
    j["volume_change_max_pct"] = result.volumeMeasurements > 0 ? nlohmann::ordered_json(result.volumeChangeMax_pct)
                                                               : nlohmann::ordered_json(nullptr);
    j["max_strain"] = result.maxStrain;
    j["strain_limit"] =
        loop.strainLimit > 0 ? nlohmann::ordered_json(loop.strainLimit) : nlohmann::ordered_json(nullptr);
    j["contact_nodes_max"] = result.contactNodesMax;
    j["footprint_cut_steps"] = result.footprintCutSteps;
    j["nan_events"] = result.nonFiniteEvents;
    j["watchdog_tripped"] = result.watchdogTripped;
    j["cut_points"] = result.cut.cutPoints;
    j["cuts"] = result.cut.cuts;
    j["cut_events"] = result.cutEvents;
    j["vertices_added"] = result.cut.verticesAdded;
    j["faces_added"] = result.cut.facesAdded;
    j["joins"] = result.cut.joins;
    j["wounds_crossed"] = result.cut.woundsCrossed;
    j["openings"] = result.cut.openings;
    j["walls_closed"] = result.cut.wallsClosed;
    j["wall_faces"] = std::count(organ.wallFaces().begin(), organ.wallFaces().end(), std::uint8_t{1});
    j["cut_length_m"] = result.cut.length_m;
    j["opened"] = result.cut.opened;
    j["cut_event_us"] = result.cutEvents > 0 ? toJson(result.cutTime_us) : nlohmann::ordered_json(nullptr);
    j["cutting_steps"] = result.cuttingSteps;
    j["cutting_force_N"] = result.cuttingSteps > 0 ? toJson(result.cuttingForce_N) : nlohmann::ordered_json(nullptr);
    j["cutting_force_min_N"] = result.cuttingSteps > 0 ? nlohmann::ordered_json(result.minCuttingForce_N) : nullptr;
    j["physics_sync_us"] = result.syncTime_us.count > 0 ? toJson(result.syncTime_us) : nlohmann::ordered_json(nullptr);
    j["invariants_ok"] = result.invariantProblems.empty();
    j["invariant_problems"] = result.invariantProblems;
    j["defects_at_load"] = result.defectsAtLoad;
    j["parts"] = nlohmann::ordered_json::array();
    for (const HapticRunResult::Part& p : result.parts)
        j["parts"].push_back({{"name", p.name},
                              {"faces_at_start", p.facesAtStart},
                              {"faces", p.faces},
                              {"boundary_edges", p.boundaryEdges},
                              {"max_displacement_m", p.maxDisplacement_m}});
    j["boundary_edges"] = after.boundaryEdges;
    j["min_angle_deg"] = after.minAngleDeg;
    j["shortest_edge_m"] = after.shortestEdge_m;
    return j;
}

}  // namespace hapticut::scene
