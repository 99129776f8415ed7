// A haptic run driven by a replayed trajectory.
#include "hapticut/scene/haptic_run.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>

#include "hapticut/collision/point_inside.h"
#include "hapticut/common/line_reader.h"
#include "hapticut/cutting/invariants.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/mesh/parts.h"
#include "hapticut/physics/volume_pressure.h"

namespace hapticut::scene {

Result<HapticRunResult, Error> runHaptic(cutting::CutModel& organ, const haptics::Trajectory& trajectory,
                                         const HapticRunConfig& config) {
    haptics::ReplayDevice device(trajectory);
    haptics::Hand hand;
    hand.device = &device;
    hand.cutThreshold_N = config.loop.cutThreshold_N;
    hand.tipRadius_m = config.loop.tipRadius_m;
    HapticRunConfig c = config;
    if (c.steps < 0) c.steps = std::lround(trajectory.duration_s() * config.loop.rate_hz) + 1;
    return runHaptic(organ, std::span<const haptics::Hand>(&hand, 1), c);
}

Result<HapticRunResult, Error> runHaptic(cutting::CutModel& organ, std::span<const haptics::Hand> hands,
                                         const HapticRunConfig& config) {
    HapticRunResult r;
    const long steps = config.steps;
    if (steps < 0 && !(config.realtime && config.stopRequested))
        return unexpected(Error{{}, 0, "an open-ended haptic run needs real time and a way to stop"});
    if (config.realtime && config.afterStep)
        return unexpected(Error{{}, 0, "a real-time haptic run takes no afterStep: it would run in the loop's period"});
    const double mass_kg = physics::totalMass(organ.model());
    // What the organ breaks before anything cuts it is the model's own (an unrepaired import), not a
    // cut's: the report tells the two apart.
    const bool checkClosed = organ.closedBeforeCuts() && config.loop.cutter.walls;
    const std::vector<std::string> atLoad = cutting::checkInvariants(organ, mass_kg, checkClosed).problems;
    const std::vector<mesh::PartSummary> partsAtStart = mesh::summariseParts(organ.mesh());
    physics::MassSpringModel& model = organ.model();
    auto created = haptics::HapticLoop::create(organ, hands, config.loop);
    if (!created) return unexpected(created.error());
    haptics::HapticLoop& loop = **created;
    r.handCount = loop.handCount();
    const long keep = std::max(0L, steps >= 0 ? std::min(config.keepSteps, steps) : config.keepSteps);
    r.keptSteps.reserve(static_cast<std::size_t>(keep));
    // The observer runs on the loop's thread in real time: it keeps running statistics, appends to
    // reserved memory, hands the step to the log's ring and runs the inside test, none of which allocates.
    // How far the run is, for the progress line: the log belongs to the stepping thread while it runs.
    std::atomic<long> stepsDone{0};
    const bool closedOrgan = organ.closedBeforeCuts();
    // Volume and strain, for the report: passes over the whole organ, taken a slice a step so that no
    // step of a large organ pays for all of it (the observer runs on the loop's thread in real time).
    // A volume sums its slices, current and rest shape alike; a cut during a pass spoils it. The rest
    // shape changes only with a cut, so a sound pass's rest volume serves every pass after it until
    // the next one.
    constexpr std::size_t kFacesPerStep = 2'000, kSpringsPerStep = 3'000;
    std::size_t faceCursor = 0, springCursor = 0;
    double volume_m3 = 0, restVolume_m3 = 0, knownRestVolume_m3 = 0;
    long passVersion = loop.topologyVersion(), knownRestVersion = -1;
    bool passSound = true;
    LatencyHistogram cuttingForce_mN(1, 20'000);  // any values, here forces in mN: never allocates
    double minCuttingForce_N = std::numeric_limits<double>::infinity();
    auto observe = [&](const haptics::StepOutput& s) {
        if (r.keptSteps.size() < r.keptSteps.capacity()) r.keptSteps.push_back(s);
        if (config.stepLog) config.stepLog->push(s);
        r.lastStep = s;
        stepsDone.store(stepsDone.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
        for (int h = 0; h < s.handCount; ++h) {
            const auto k = static_cast<std::size_t>(h);
            r.hands[k].maxForce_N = std::max(r.hands[k].maxForce_N, s.hands[k].force_N.norm());
            r.hands[k].contactSteps += s.hands[k].contact;
            if (s.hands[k].cutting) {
                ++r.cuttingSteps;
                cuttingForce_mN.record(1e3 * s.hands[k].force_N.norm());
                minCuttingForce_N = std::min(minCuttingForce_N, s.hands[k].force_N.norm());
            }
        }
        // The ray-parity test needs a closed surface: a closed organ stays closed while walls close
        // every wound; an opening left without walls lets the proxy into the organ, no penetration.
        if (closedOrgan && loop.cutter().woundsClosed()) {
            ++r.penetrationMeasuredSteps;
            for (int h = 0; h < s.handCount; ++h)
                r.maxProxyPenetration_m = std::max(
                    r.maxProxyPenetration_m, collision::penetrationDepth(loop.bvh(), loop.surface(),
                                                                         s.hands[static_cast<std::size_t>(h)].proxy_m));
        }
        if (closedOrgan) {
            const std::span<const mesh::Face> faces = loop.surface().faces;
            const std::size_t end = std::min(faces.size(), faceCursor + kFacesPerStep);
            const std::span<const mesh::Face> slice = faces.subspan(faceCursor, end - faceCursor);
            volume_m3 += physics::enclosedVolume(model.nodes.position, slice);
            const bool restKnown = knownRestVersion == passVersion;
            if (!restKnown) restVolume_m3 += physics::enclosedVolume(model.nodes.restPosition, slice);
            passSound = passSound && loop.topologyVersion() == passVersion && loop.cutter().woundsClosed();
            faceCursor = end;
            if (faceCursor == faces.size()) {
                if (passSound && !restKnown) knownRestVolume_m3 = restVolume_m3, knownRestVersion = passVersion;
                const double rest_m3 = restKnown ? knownRestVolume_m3 : restVolume_m3;
                if (passSound && rest_m3 > 0) {
                    r.volumeChangeMax_pct =
                        std::max(r.volumeChangeMax_pct, 100 * std::abs(volume_m3 - rest_m3) / rest_m3);
                    ++r.volumeMeasurements;
                }
                faceCursor = 0, volume_m3 = restVolume_m3 = 0;
                passVersion = loop.topologyVersion(), passSound = true;
            }
        }
        const std::size_t springEnd = std::min(model.springs.size(), springCursor + kSpringsPerStep);
        r.maxStrain = std::max(r.maxStrain, physics::maxStrain(model, springCursor, springEnd));
        springCursor = springEnd == model.springs.size() ? 0 : springEnd;
        // Over the nodes the step moved, so that a measurement on a large organ costs the region, not the organ.
        r.maxDisplacement_m = std::max(r.maxDisplacement_m, physics::maxDisplacement(model, loop.movedNodes()));
        if (config.afterStep) config.afterStep(s, loop);
    };
    if (config.realtime) {
        haptics::RealTimeScheduler clock(loop);
        if (auto error = clock.start(steps, observe)) return unexpected(std::move(*error));
        auto lastProgress = std::chrono::steady_clock::now();
        std::optional<std::chrono::steady_clock::time_point> noticed;
        while (clock.running()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            if (config.stopRequested && config.stopRequested()) {
                noticed = std::chrono::steady_clock::now();
                break;
            }
            if (config.progress && std::chrono::steady_clock::now() - lastProgress > std::chrono::seconds(1)) {
                lastProgress = std::chrono::steady_clock::now();
                config.progress(stepsDone.load(std::memory_order_relaxed));
            }
        }
        clock.stop();
        r.hapticScheduling = clock.scheduling();
        r.stoppedEarly = config.stopRequested && config.stopRequested();
        if (noticed)
            r.stopLatency_s = config.stopRequestedAgo_s
                                  ? config.stopRequestedAgo_s()
                                  : std::chrono::duration<double>(std::chrono::steady_clock::now() - *noticed).count();
    } else {
        auto lastProgress = std::chrono::steady_clock::now();
        auto keepGoing = [&] {
            if (config.progress && std::chrono::steady_clock::now() - lastProgress > std::chrono::seconds(1)) {
                lastProgress = std::chrono::steady_clock::now();
                config.progress(stepsDone.load(std::memory_order_relaxed));
            }
            r.stoppedEarly = config.stopRequested && config.stopRequested();
            return !r.stoppedEarly;
        };
        haptics::runSimulated(loop, steps, observe, keepGoing);
        if (r.stoppedEarly && config.stopRequestedAgo_s) r.stopLatency_s = config.stopRequestedAgo_s();
    }
    if (config.stepLog) r.droppedLogSteps = config.stepLog->droppedSteps();
    const haptics::LoopStats& st = loop.stats();
    r.steps = st.steps;
    r.simTime_s = static_cast<double>(st.steps) / config.loop.rate_hz;
    r.wallTime_s = st.wallTime_s;
    r.hapticRate_hz = st.wallTime_s > 0 ? static_cast<double>(st.steps) / st.wallTime_s : 0;
    r.stepTime_us = st.stepTime_us.summary();
    r.periodError_us = st.periodError_us.summary();
    r.overruns = st.overruns;
    r.missedPeriods = st.missedPeriods;
    r.stalls = st.stalls;
    r.contactSteps = st.contactSteps;
    r.contactNodesMax = st.contactNodesMax;
    r.footprintCutSteps = st.footprintCutSteps;
    r.nonFiniteEvents = st.nonFiniteEvents;
    r.watchdogTripped = st.watchdogTripped;
    r.maxForce_N = st.maxForce_N;
    for (int h = 0; h < r.handCount; ++h) {
        r.proxyPushOuts += loop.proxy(h).pushOuts();
        r.proxyDeepestPushOut_m = std::max(r.proxyDeepestPushOut_m, loop.proxy(h).deepestPushOut_m());
    }
    r.finalMaxDisplacement_m = physics::maxDisplacement(model);
    r.cut = loop.cutter().stats();
    r.cutEvents = st.cutEvents;
    r.cutTime_us = st.cutTime_us.summary();
    const Summary cutting = cuttingForce_mN.summary();
    r.cuttingForce_N = {cutting.mean / 1e3, cutting.p50 / 1e3, cutting.p99 / 1e3, cutting.max / 1e3, 0, cutting.count};
    r.minCuttingForce_N = r.cuttingSteps > 0 ? minCuttingForce_N : 0;
    r.syncTime_us = st.syncTime_us.summary();
    r.defectsAtLoad = atLoad;
    const std::vector<mesh::PartSummary> partsAtEnd = mesh::summariseParts(organ.mesh());
    for (std::size_t p = 0; p < partsAtEnd.size(); ++p)
        r.parts.push_back({partsAtEnd[p].name, p < partsAtStart.size() ? partsAtStart[p].faces : 0, partsAtEnd[p].faces,
                           partsAtEnd[p].boundaryEdges, 0.0});
    if (!r.parts.empty()) {
        const mesh::SurfaceMesh& m = organ.mesh();
        for (std::size_t f = 0; f < m.faces.size(); ++f)
            for (std::uint32_t v : m.faces[f]) {
                double& d = r.parts[m.faceParts[f]].maxDisplacement_m;
                d = std::max(d, (model.nodes.position[v] - model.nodes.restPosition[v]).norm());
            }
    }
    for (std::string& problem : cutting::checkInvariants(organ, mass_kg, checkClosed).problems)
        if (std::find(atLoad.begin(), atLoad.end(), problem) == atLoad.end())
            r.invariantProblems.push_back(std::move(problem));
    r.scheme = loop.scheme();
    r.substeps = loop.substeps();
    r.solver = st.solver;
    r.multiRate = loop.multiRate();
    r.volumeKept = st.volumeKept;
    r.multiRateFrom_s =
        st.multiRateFromStep >= 0 ? static_cast<double>(st.multiRateFromStep) / config.loop.rate_hz : -1;
    r.multiRateSwitchSteps = st.multiRateSwitchSteps;
    r.physicsRate_hz = st.wallTime_s > 0 ? static_cast<double>(st.physicsSteps) / st.wallTime_s : 0;
    r.physicsRealtimeFactor = st.wallTime_s > 0 ? st.physicsTime_s / st.wallTime_s : 0;
    r.maxPhysicsStep_s = config.loop.maxPhysicsStep_s;
    r.physicsStepTime_us = st.physicsStepTime_us.summary();
    r.physicsTimeLost_s = st.physicsTimeLost_s;
    r.physicsLagAtEnd_s = std::max(0.0, st.wallTime_s - st.physicsTime_s - st.physicsTimeLost_s);
    return r;
}

}  // namespace hapticut::scene
