// `hapticut run`: a headless simulation of a model, with an optional press, a JSON report and mesh export.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <set>

#include "commands.h"
#include "hapticut/common/line_reader.h"
#include "hapticut/common/output_path.h"
#include "hapticut/common/stop_signal.h"
#include "hapticut/common/text_file.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/step_log.h"
#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/scene/haptic_run.h"
#include "hapticut/scene/headless_run.h"
#include "hapticut/scene/model_info.h"
#include "hapticut/scene/model_size.h"
#include "hapticut/scene/open_device.h"
#include "hapticut/scene/scene.h"
#include "provenance.h"
#include "terminal.h"
#include "unit_options.h"

namespace hapticut::app {

namespace {

struct RunOptions {
    std::string model = "heart";
    int triangles = 1619;
    std::string integrator = "auto";
    double solverTolerance = physics::SolverSettings{}.tolerance;
    double solverForceTolerance_N = physics::SolverSettings{}.forceTolerance_N;
    int solverMaxIterations = physics::SolverSettings{}.maxIterations;
    unsigned solverThreads = physics::SolverSettings{}.threads;
    double dt_s = 1e-3;
    long steps = 1000;
    bool stepsGiven = false;
    std::string forceAt, force;
    double forceUntil_s = -1;
    std::string exportMesh, report;
    std::string trajectory, tool = "probe", forceLog, record;
    std::vector<std::string> devices;  // --device, once per hand
    std::string secondTool = "probe";  // the second hand's
    bool noWorkspaceFit = false;
    std::string sdlControl = "position";
    std::string hdLibrary;
    bool realtime = false;
    double rate_hz = 1000;
    double couplingStiffness_N_per_m = haptics::LoopConfig{}.couplingStiffness_N_per_m;
    std::string friction;  // "static,dynamic"
    std::string scene;
    std::vector<std::string> settings;  // --set KEY=VALUE, over the scene's keys
    UnitOptions units;
    std::set<std::string> given;  // options given on the command line: they override the scene
};

/// The scene file (or the built-in default) with every option the command line gave set over it.
/// Nothing (with the reason printed) when an option's value is malformed: exit 2.
std::optional<scene::SceneRequest> sceneRequest(const RunOptions& o) {
    scene::SceneRequest request;
    request.file = o.scene;
    for (const std::string& setting : o.settings) {
        const auto line = scene::settingLine(setting);
        if (!line) {
            std::cerr << "hapticut run: --set " << line.error() << "\n";
            return std::nullopt;
        }
        request.overlay += *line;
    }
    scene::SceneOverrides& over = request.overrides;
    o.units.applyTo(over);
    auto given = [&](const char* option) { return o.given.count(option) > 0; };
    if (given("--model")) over.model = o.model;
    if (given("--triangles")) over.triangles = o.triangles;
    if (given("--integrator")) {
        over.scheme = physics::parseScheme(o.integrator);
        if (!over.scheme) {
            std::cerr << "hapticut run: unknown integrator '" << o.integrator
                      << "': expected auto, euler, midpoint, rk4, symplectic or implicit\n";
            return std::nullopt;
        }
    }
    if (given("--solver-tolerance")) over.solverTolerance = o.solverTolerance;
    if (given("--solver-force-tolerance")) over.solverForceTolerance_N = o.solverForceTolerance_N;
    if (given("--solver-iterations")) over.solverMaxIterations = o.solverMaxIterations;
    if (given("--solver-threads")) over.solverThreads = o.solverThreads;
    if (given("--rate")) over.rate_hz = o.rate_hz;
    if (given("--coupling-stiffness")) over.couplingStiffness_N_per_m = o.couplingStiffness_N_per_m;
    if (given("--friction")) {
        const auto comma = o.friction.find(',');
        double mus = 0, mud = 0;
        if (comma == std::string::npos || !parseFiniteDouble(o.friction.substr(0, comma), mus) ||
            !parseFiniteDouble(o.friction.substr(comma + 1), mud) || mus < 0 || mud < 0 || mud > mus) {
            std::cerr << "hapticut run: --friction takes 'STATIC,DYNAMIC' with 0 <= DYNAMIC <= STATIC, found '"
                      << o.friction << "'\n";
            return std::nullopt;
        }
        over.friction = std::array<double, 2>{mus, mud};
    }
    if (given("--trajectory")) over.trajectory = o.trajectory;
    return request;
}

/// The fields every run report starts with: what was simulated, with which integrator (`requested`,
/// which may be auto, and `scheme`, the one used).
nlohmann::ordered_json reportHeader(const scene::ModelSource& source, const physics::MassSpringModel& model,
                                    physics::Scheme requested, physics::Scheme scheme) {
    nlohmann::ordered_json j;
    j["provenance"] = provenance();
    j["model"] = source.name;
    j["vertices"] = source.mesh.positions.size();
    j["vertex_order"] = scene::vertexOrderJson(source);
    j["faces"] = source.mesh.faces.size();
    j["springs"] = model.springs.size();
    j["integrator"] = physics::schemeName(scheme);
    j["integrator_requested"] = physics::schemeName(requested);
    return j;
}

/// Writes the deformed mesh (rest mesh `rest` at the model's positions), if asked; false on failure (already reported).
bool exportDeformed(const std::string& file, const mesh::SurfaceMesh& rest, const scene::ModelSource& source,
                    const physics::MassSpringModel& model) {
    if (file.empty()) return true;
    mesh::SurfaceMesh deformed = rest;
    deformed.positions = model.nodes.position;
    mesh::computeFaceNormals(deformed);
    if (const auto error = mesh::io::saveMesh(file, deformed, source.physics)) {
        std::cerr << error->toString() << "\n";
        return false;
    }
    std::cout << "wrote the deformed mesh to " << file << "\n";
    return true;
}

/// The tip of --tool or --second-tool; nothing (with the reason printed, and `status` set to the exit
/// code) for an unknown name (2) or a tool file that does not load (1).
std::optional<scene::ToolTip> toolTip(const scene::SceneFile& settings, const std::string& name, int& status) {
    auto tip = scene::toolTip(settings, name);
    if (tip) return *tip;
    const bool unknownName = tip.error().file.empty();
    std::cerr << (unknownName ? "hapticut run: " : "") << tip.error().toString() << "\n";
    status = unknownName ? 2 : 1;
    return std::nullopt;
}

/// Organs from this size on take long enough to build and prepare that each phase gets a line.
constexpr std::size_t kTrianglesWorthAPhaseLine = 150'000;

int runHapticMode(const RunOptions& o, const std::filesystem::path& sceneFile, scene::SceneFile settings) {
    // The hands: the trajectory (--trajectory, or the scene's replay device) is the first hand's replay;
    // each --device adds one. Without either, the scene's [[devices]] are the hands.
    const std::string trajectory = settings.deviceBackend == "replay" ? settings.trajectory : "";
    const physics::Scheme scheme = settings.scheme;
    const double rate_hz = settings.rate_hz;
    std::vector<haptics::DeviceName> specs;
    std::vector<const scene::SceneDevice*> fromScene;  // per hand: its [[devices]] entry, if it has one
    if (!trajectory.empty()) specs.push_back({haptics::DeviceKind::Replay, trajectory});
    for (const std::string& text : o.devices) {
        auto spec = haptics::parseDeviceName(text);
        if (!spec) {
            std::cerr << "hapticut run: " << spec.error().toString() << "\n";
            return 2;
        }
        specs.push_back(*spec);
    }
    if (specs.empty())
        for (const scene::SceneDevice& d : settings.devices) specs.push_back(d.device), fromScene.push_back(&d);
    fromScene.resize(specs.size(), nullptr);
    for (const haptics::DeviceName& spec : specs)
        if (spec.kind == haptics::DeviceKind::Virtual) {
            std::cerr << "hapticut run: the virtual device is moved by a program or the viewer's mouse, and nothing "
                         "moves it in a headless run: "
                         "give replay:FILE, openhaptics[:NAME] or sdl[:INDEX]\n";
            return 2;
        }
    if (specs.size() > static_cast<std::size_t>(haptics::kMaxHands)) {
        std::cerr << "hapticut run: " << specs.size() << " devices (--trajectory counts as one): at most "
                  << haptics::kMaxHands << ", one per hand\n";
        return 2;
    }
    // Each hand's tool: the command line's when it names one, else its [[devices]] entry's, else the probe.
    std::vector<std::string> toolOf(specs.size());
    for (std::size_t h = 0; h < specs.size(); ++h) {
        const char* option = h == 0 ? "--tool" : "--second-tool";
        const std::string& given = h == 0 ? o.tool : o.secondTool;
        toolOf[h] = !o.given.count(option) && fromScene[h] && !fromScene[h]->tool.empty() ? fromScene[h]->tool : given;
    }
    int toolStatus = 0;
    std::vector<scene::ToolTip> tipOf;
    for (const std::string& name : {o.tool, o.secondTool})  // both checked, used or not: a typo is an error either way
        if (!toolTip(settings, name, toolStatus)) return toolStatus;
    for (const std::string& name : toolOf) {
        const auto tip = toolTip(settings, name, toolStatus);
        if (!tip) return toolStatus;
        tipOf.push_back(*tip);
    }
    const std::string& firstTool = toolOf.empty() ? o.tool : toolOf[0];
    if (o.sdlControl != "position" && o.sdlControl != "rate") {
        std::cerr << "hapticut run: --sdl-control takes position or rate, found '" << o.sdlControl << "'\n";
        return 2;
    }
    // A large organ takes seconds to build and prepare (about 15 s and 8 s at a million triangles): each
    // phase says so as it starts, instead of a silent wait.
    const bool slowToBuild =
        settings.model == "heart" && static_cast<std::size_t>(settings.triangles) >= kTrianglesWorthAPhaseLine;
    if (slowToBuild) std::cerr << "hapticut run: building the heart of " << settings.triangles << " triangles\n";
    const auto scene = app::assembleScene(sceneFile, std::move(settings));
    if (!scene) return 1;
    const scene::ModelSource* source = &scene->source;
    cutting::CutModel organ = scene->makeOrgan();
    const physics::MassSpringModel& model = organ.model();

    // Open the devices; a live one (not a replay) means real time, until --steps or Ctrl-C.
    scene::DeviceOptions deviceOptions;
    deviceOptions.fitWorkspace = !o.noWorkspaceFit;
    deviceOptions.hdLibrary = o.hdLibrary;
    deviceOptions.sdlControl = o.sdlControl == "rate" ? haptics::SdlControl::Rate : haptics::SdlControl::Position;
    std::vector<scene::OpenedDevice> opened;
    double replayDuration_s = 0;
    bool live = false;
    for (std::size_t h = 0; h < specs.size(); ++h) {
        const haptics::DeviceName& spec = specs[h];
        const scene::DeviceOptions options =
            fromScene[h] ? scene::deviceOptionsFor(*fromScene[h], !o.noWorkspaceFit, o.hdLibrary) : deviceOptions;
        auto device = scene::openDeviceFor(*scene, spec, options);
        if (!device) {
            std::cerr << "hapticut run: " << device.error().toString() << "\n";
            return 1;
        }
        if (const auto* replay = dynamic_cast<const haptics::ReplayDevice*>(device->device.get())) {
            replayDuration_s = std::max(replayDuration_s, replay->trajectory().duration_s());
            std::vector<Vec3> path;
            for (const haptics::TrajectoryPoint& p : replay->trajectory().points) path.push_back(p.sample.position_m);
            if (const auto far =
                    scene::farFromModelWarning(source->mesh.positions, path, "the device's path", spec.argument))
                std::cerr << "warning: " << far->toString() << "\n";
        } else
            live = true;
        std::cerr << "hapticut run: hand " << opened.size() + 1 << ": " << device->description << "\n";
        opened.push_back(std::move(*device));
    }
    std::vector<haptics::Hand> hands;
    for (std::size_t h = 0; h < opened.size(); ++h)
        hands.push_back(scene::makeHand(*scene, *opened[h].device, tipOf[h], fromScene[h]));

    scene::HapticRunConfig config;
    config.loop = scene::loopConfigFor(*scene, tipOf[0]);
    config.steps = o.stepsGiven ? o.steps : live ? -1 : std::lround(replayDuration_s * rate_hz) + 1;
    config.realtime = o.realtime || live;
    StopSignal stopSignal;
    config.stopRequested = [] { return StopSignal::requested(); };
    config.stopRequestedAgo_s = [] { return StopSignal::secondsSinceRequest(); };
    Progress progress("hapticut run: steps (Ctrl-C ends the run)");
    config.progress = [&](long steps) { progress.update(steps, config.steps); };
    config.tool = firstTool;
    std::cerr << "hapticut run: " << source->name << ": " << model.nodes.size() << " nodes; " << firstTool
              << (hands.size() > 1 ? " and " + toolOf[1] : "") << ", "
              << (config.steps >= 0 ? std::to_string(config.steps) + " steps" : std::string("until Ctrl-C")) << " at "
              << rate_hz << " Hz, " << (config.realtime ? "real time" : "simulated time") << "\n";
    if (organ.mesh().faces.size() >= kTrianglesWorthAPhaseLine)
        std::cerr << "hapticut run: preparing the collision tree and the integrator for " << organ.mesh().faces.size()
                  << " triangles\n";
    // The force log and the recording are written as the run goes, so a run of any length holds
    // constant memory; they replace their targets only when the run has ended.
    std::vector<haptics::StepLogWriter::Target> logTargets;
    if (!o.forceLog.empty()) logTargets.push_back({o.forceLog, haptics::StepLogColumns::ForceLog});
    if (!o.record.empty()) logTargets.push_back({o.record, haptics::StepLogColumns::Recording});
    std::unique_ptr<haptics::StepLogWriter> stepLog;
    if (!logTargets.empty()) {
        auto writer = haptics::StepLogWriter::open(std::move(logTargets), config.realtime
                                                                              ? haptics::StepLogWriter::WhenFull::Drop
                                                                              : haptics::StepLogWriter::WhenFull::Wait);
        if (!writer) {
            std::cerr << writer.error().toString() << "\n";
            return 1;
        }
        stepLog = std::move(*writer);
        config.stepLog = stepLog.get();
    }
    auto run = scene::runHaptic(organ, hands, config);
    progress.finish();
    if (!run) {
        std::cerr << "hapticut run: " << run.error().toString() << "\n";
        return 1;
    }
    const scene::HapticRunResult& r = *run;
    if (StopSignal::requested())
        std::cerr << "hapticut run: stopped by signal " << StopSignal::signalNumber() << " after " << r.steps
                  << " steps; the devices were left at zero force " << std::lround(std::max(r.stopLatency_s, 0.0) * 1e3)
                  << " ms after the signal\n";

    std::cout << r.steps << " haptic steps (" << r.simTime_s << " s simulated) in " << r.wallTime_s
              << " s wall: " << r.hapticRate_hz << " steps/s; step " << r.stepTime_us.p50 << " us p50, "
              << r.stepTime_us.p99 << " us p99, " << r.stepTime_us.max << " us max; integrator "
              << physics::schemeName(r.scheme)
              << (r.substeps > 1 ? " in " + std::to_string(r.substeps) + " substeps" : std::string()) << "\n"
              << solverLine(r.scheme, r.solver);
    if (r.multiRate && r.multiRateFrom_s > 0)
        std::cout << "the physics took more than half the period: multi-rate from t = " << r.multiRateFrom_s << " s\n";
    std::cout << (r.multiRate ? "multi-rate" : "single-rate") << " physics: " << r.physicsRate_hz << " steps/s, "
              << r.physicsRealtimeFactor << " simulated s per wall s; step " << r.physicsStepTime_us.p50 / 1e3
              << " ms p50, " << r.physicsStepTime_us.p99 / 1e3 << " ms p99\n";
    if (r.multiRate && config.realtime)
        std::cout << "the tissue fell behind by " << r.physicsTimeLost_s << " s where the physics was more than "
                  << 2 * r.maxPhysicsStep_s << " s behind (twice the longest step), and was " << r.physicsLagAtEnd_s
                  << " s behind the wall clock at the end (the step in progress, what it owed and a frame coming in)\n";
    if (config.realtime)
        std::cout << "haptic thread: " << r.hapticScheduling
                  << (r.hapticScheduling.rfind("normal: ", 0) == 0
                          ? " (grant it with `sudo setcap cap_sys_nice+ep` on the hapticut binary, or an rtprio limit)"
                          : "")
                  << "\n";
    if (config.realtime)
        std::cout << "period error " << r.periodError_us.p50 << " us p50, " << r.periodError_us.p99 << " us p99, "
                  << r.periodError_us.max << " us max; overruns " << r.overruns << " (" << r.missedPeriods
                  << (r.missedPeriods == 1 ? " period" : " periods") << " missed, " << r.stalls << " stall"
                  << (r.stalls == 1 ? "" : "s") << " after which the force ramped back in)\n";
    std::cout << "contact in " << r.contactSteps << " steps; max force " << r.maxForce_N << " N; max proxy penetration "
              << r.maxProxyPenetration_m << " m (measured in " << r.penetrationMeasuredSteps
              << " steps); max tissue displacement " << r.maxDisplacement_m * 1e3 << " mm, "
              << r.finalMaxDisplacement_m * 1e3 << " mm at the end\n"
              << "volume " << (r.volumeKept ? "kept by a pressure" : "free") << ": "
              << (r.volumeMeasurements > 0 ? std::to_string(r.volumeChangeMax_pct) + "% largest change"
                                           : std::string("not measured (the surface is open)"))
              << "; largest spring strain " << r.maxStrain * 100 << "%\n";
    if (r.handCount > 1)
        for (int h = 0; h < r.handCount; ++h)
            std::cout << "hand " << h + 1 << " (" << specs[static_cast<std::size_t>(h)].toString() << ", "
                      << toolOf[static_cast<std::size_t>(h)] << "): max force "
                      << r.hands[static_cast<std::size_t>(h)].maxForce_N << " N, contact in "
                      << r.hands[static_cast<std::size_t>(h)].contactSteps << " steps\n";
    if (r.watchdogTripped)
        std::cout << "watchdog tripped: " << r.nonFiniteEvents << " non-finite value(s); force was zeroed\n";
    const mesh::MeshReport after = mesh::validateMesh(organ.mesh());
    if (r.cut.cuts > 0)
        std::cout << "cut " << r.cut.cuts << " time(s): " << r.cut.cutPoints << " cut points, " << r.cut.length_m * 1e3
                  << " mm long, " << r.cut.verticesAdded << " vertices and " << r.cut.facesAdded << " faces added, "
                  << (r.cut.opened ? "opened " + std::to_string(r.cut.openings) + " point(s), " +
                                         std::to_string(r.cut.wallsClosed) + " closed with walls"
                                   : "not opened")
                  << (r.cut.woundsCrossed > 0
                          ? ", " + std::to_string(r.cut.woundsCrossed) + " earlier wound(s) cut through"
                          : std::string())
                  << (r.cut.joins > 0
                          ? ", " + std::to_string(r.cut.joins) + " join(s) with a boundary or an earlier wound"
                          : std::string())
                  << "; " << after.boundaryEdges << " boundary edges now; cut event " << r.cutTime_us.p50 << " us p50, "
                  << r.cutTime_us.max << " us max\n"
                  << "the blade felt " << r.cuttingForce_N.p50 << " N p50, " << r.minCuttingForce_N << " N min, "
                  << r.cuttingForce_N.max << " N max over the " << r.cuttingSteps << " steps it was cutting\n";
    else if (std::isfinite(config.loop.cutThreshold_N))
        std::cout << "no cut: the " << firstTool << " never pressed harder than its " << config.loop.cutThreshold_N
                  << " N threshold\n";
    if (!r.defectsAtLoad.empty())
        std::cout << "the model had " << r.defectsAtLoad.size() << (r.defectsAtLoad.size() >= 20 ? " or more" : "")
                  << " defects before the run (not from cutting; hapticut convert --repair fixes them): "
                  << r.defectsAtLoad.front() << "\n";
    if (!r.invariantProblems.empty())
        std::cout << (r.cutEvents > 0 ? "the cut broke the organ: " : "the run broke the organ: ")
                  << r.invariantProblems.front() << "\n";

    int status = r.watchdogTripped ? 3 : 0;
    // Ctrl-C is how a run with a live device and no --steps ends; a run with a set length (--steps, a
    // replay) was cut short.
    if (r.stoppedEarly && config.steps >= 0) status = 128 + StopSignal::signalNumber();
    if (stepLog) {
        for (const Error& error : stepLog->finish()) {
            std::cerr << error.toString() << "\n";
            status = 1;
        }
        if (status != 1)
            std::cout << "wrote " << stepLog->rowsWritten() << " steps to "
                      << (o.forceLog.empty() ? o.record
                          : o.record.empty() ? o.forceLog
                                             : o.forceLog + " and " + o.record)
                      << "\n";
        if (r.droppedLogSteps > 0)
            std::cout << r.droppedLogSteps << " steps missing from the log: the disk did not keep up\n";
    }
    if (!exportDeformed(o.exportMesh, organ.mesh(), *source, model)) status = 1;
    if (!o.report.empty()) {
        scene::HapticRunRequest request;
        request.requestedScheme = scheme;
        request.rate_hz = rate_hz;
        request.tool = firstTool;
        request.trajectory = trajectory;
        request.realtime = config.realtime;
        request.stepsRequested = config.steps;
        request.stoppedBySignal = StopSignal::requested();
        for (std::size_t h = 0; h < specs.size(); ++h)
            request.hands.push_back({specs[h].toString(), opened[h].description, toolOf[h], tipOf[h]});
        const nlohmann::ordered_json report = scene::hapticRunReport(*source, organ, config.loop, request, r);
        nlohmann::ordered_json j;
        j["provenance"] = provenance();
        for (const auto& [key, value] : report.items()) j[key] = value;
        if (!writeJson(o.report, j)) return 1;
        std::cout << "wrote the report to " << o.report << "\n";
    }
    return status;
}

int run(RunOptions& o) {
    // Every file the run will write, checked before it starts: a typo must not cost a long run its results.
    if (const Status unwritable = checkOutputPaths({o.report, o.forceLog, o.record, o.exportMesh})) {
        std::cerr << "hapticut run: " << unwritable->toString() << "\n";
        return 2;
    }
    const auto request = sceneRequest(o);
    if (!request) return 2;
    auto settings = scene::sceneSettings(*request);
    if (!settings) {
        std::cerr << settings.error().toString() << "\n";
        return 1;
    }
    if (settings->deviceBackend == "replay" || !o.devices.empty() || !settings->devices.empty()) {
        if (!o.force.empty()) {
            std::cerr << "hapticut run: --force and --trajectory do not go together: the trajectory's device presses "
                         "the model\n";
            return 2;
        }
        return runHapticMode(o, request->file, std::move(*settings));
    }
    scene::RunConfig config;
    config.scheme = settings->scheme;
    config.solver = settings->solver;
    // A scene file's rate sets the step unless the command line gives one.
    const bool stepGiven = o.given.count("--dt") || o.given.count("--rate");
    config.dt_s = !o.scene.empty() && !stepGiven ? 1 / settings->rate_hz : o.dt_s;
    config.steps = o.steps;
    if (o.forceAt.empty() != o.force.empty()) {
        std::cerr << "hapticut run: --force-at and --force go together\n";
        return 2;
    }
    if (!o.force.empty()) {
        const auto at = parseVec3(o.forceAt), force = parseVec3(o.force);
        if (!at || !force) {
            std::cerr << "hapticut run: --force-at and --force take three numbers 'X,Y,Z', found '"
                      << (at ? o.force : o.forceAt) << "'\n";
            return 2;
        }
        config.force = scene::PointForce{*at, *force, o.forceUntil_s >= 0 ? o.forceUntil_s : 1e300};
    }

    const auto scene = app::assembleScene(request->file, std::move(*settings));
    if (!scene) return 1;
    const scene::ModelSource* source = &scene->source;
    if (config.force)
        if (const auto far = scene::farFromModelWarning(source->mesh.positions, std::span(&config.force->at_m, 1),
                                                        "--force-at " + o.forceAt))
            std::cerr << "warning: " << far->toString() << "\n";
    physics::MassSpringModel model = scene->buildModel();
    std::cerr << "hapticut run: " << source->name << ": " << model.nodes.size() << " nodes, " << model.springs.size()
              << " springs, integrator " << physics::schemeName(config.scheme) << ", dt " << config.dt_s << " s, "
              << config.steps << " steps\n";

    const StopSignal stopSignal;
    config.stopRequested = [] { return StopSignal::requested(); };
    Progress progress("simulating");
    const auto run = scene::runHeadless(
        model, config, [&](long done, long total) { progress.update(done, total); },
        [](const std::string& what) { std::cerr << "\nhapticut run: slow: " << what << " (Ctrl-C stops it)\n"; });
    progress.finish();
    if (!run) {
        std::cerr << "hapticut run: " << run.error().toString() << "\n";
        return 2;
    }
    const scene::RunResult& r = *run;
    if (r.stoppedEarly)
        std::cerr << "hapticut run: stopped by signal " << StopSignal::signalNumber() << " after " << r.steps << " of "
                  << config.steps << " steps\n";

    const bool implicit = r.scheme == physics::Scheme::BackwardEuler;
    std::cout << "simulated " << r.simTime_s << " s in " << r.wallTime_s << " s wall; step " << r.step_us.mean
              << " us mean, " << r.step_us.p99 << " us p99 (";
    if (implicit)
        std::cout << "implicit, one solve each)\n" << solverLine(r.scheme, r.solver);
    else
        std::cout << r.substeps << " substep" << (r.substeps == 1 ? "" : "s") << " each of "
                  << physics::schemeName(r.scheme) << ", stable below " << r.stableStep_s * 1e3 << " ms)\n";
    if (config.force)
        std::cout << "pressed node " << r.forceNode << " with " << config.force->force_N.norm() << " N: displaced "
                  << r.forceNodeDisplacementAtRelease_m * 1e3 << " mm at release, "
                  << r.forceNodeDisplacementEnd_m * 1e3 << " mm at the end\n";
    if (r.recoveryTime_s >= 0)
        std::cout << "after release every node was back within " << scene::kRecoveredDistance_m * 1e3
                  << " mm of rest in " << r.recoveryTime_s * 1e3 << " ms\n";
    std::cout << "max displacement " << r.maxDisplacement_m * 1e3 << " mm during the run, "
              << r.finalMaxDisplacement_m * 1e3 << " mm at the end; kinetic energy at the end " << r.kineticEnergyEnd_J
              << " J; non-finite steps " << r.nanEvents << "\n";

    int status = r.stoppedEarly ? 128 + StopSignal::signalNumber() : r.nanEvents > 0 ? 3 : 0;
    if (!exportDeformed(o.exportMesh, source->mesh, *source, model)) status = 1;
    if (!o.report.empty()) {
        nlohmann::ordered_json j = reportHeader(*source, model, config.scheme, r.scheme);
        j["dt"] = config.dt_s;
        j["steps"] = r.steps;
        j["steps_requested"] = config.steps;
        j["stopped_by_signal"] = r.stoppedEarly;
        j["substeps"] = r.substeps;
        j["solver"] = solverJson(r.scheme, r.solver, config.solver);
        j["stable_dt_s"] = implicit ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.stableStep_s);
        j["sim_time_s"] = r.simTime_s;
        j["wall_time_s"] = r.wallTime_s;
        j["step_us"] = toJson(r.step_us);
        j["max_displacement_m"] = r.maxDisplacement_m;
        j["final_max_displacement_m"] = r.finalMaxDisplacement_m;
        j["kinetic_energy_end_J"] = r.kineticEnergyEnd_J;
        j["nan_events"] = r.nanEvents;
        j["total_mass_kg"] = physics::totalMass(model);
        if (config.force) {
            j["force"] = {{"node", r.forceNode},
                          {"at_m", toJson(config.force->at_m)},
                          {"force_N", toJson(config.force->force_N)},
                          {"until_s", std::min(config.force->until_s, r.simTime_s)},
                          {"node_displacement_at_release_m", r.forceNodeDisplacementAtRelease_m},
                          {"node_displacement_end_m", r.forceNodeDisplacementEnd_m},
                          {"recovery_time_s", r.recoveryTime_s >= 0 ? nlohmann::ordered_json(r.recoveryTime_s)
                                                                    : nlohmann::ordered_json(nullptr)}};
        }
        if (!writeJson(o.report, j)) return 1;
        std::cout << "wrote the report to " << o.report << "\n";
    }
    return status;
}

}  // namespace

Command addRunCommand(CLI::App& app) {
    auto o = std::make_shared<RunOptions>();
    CLI::App* cmd = app.add_subcommand("run", "Simulate a model headless and report what happened");
    cmd->add_option("--model", o->model, "'heart' (procedural) or a model file (.txt thesis format, .obj, .ply)")
        ->capture_default_str();
    addUnitOptions(cmd, o->units);
    cmd->add_option("--triangles", o->triangles, "Triangle count of the procedural heart")
        ->capture_default_str()
        ->check(CLI::Range(12, 20'000'000));
    cmd->add_option("--integrator", o->integrator,
                    "auto (RK4 where one step per period is stable, else implicit), euler, midpoint, rk4, "
                    "symplectic or implicit (backward Euler)")
        ->capture_default_str();
    cmd->add_option("--solver-tolerance", o->solverTolerance,
                    "The implicit solve stops below this residual, relative to the right-hand side")
        ->capture_default_str()
        ->check(CLI::Range(1e-14, 1.0));
    cmd->add_option("--solver-force-tolerance", o->solverForceTolerance_N,
                    "Or once no node's residual force exceeds this (N): tissue near rest needs no finer solve (0: off)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--solver-iterations", o->solverMaxIterations, "The implicit solve's iteration cap")
        ->capture_default_str()
        ->check(CLI::Range(1, physics::kMaxSolverIterations));
    cmd->add_option("--solver-threads", o->solverThreads,
                    "Threads that share the implicit solve, its own included; 0: every core but two (one for the "
                    "haptic loop, one for the rest), here " +
                        std::to_string(physics::automaticSolverThreads()) +
                        "; the results are the same with any number")
        ->capture_default_str()
        ->check(CLI::Range(0u, physics::kMaxSolverThreads));
    cmd->add_option("--dt", o->dt_s, "Time step in seconds")->capture_default_str()->check(CLI::Range(1e-7, 1.0));
    cmd->add_option("--steps", o->steps, "Number of steps")
        ->capture_default_str()
        ->check(CLI::Range(0L, 1'000'000'000L));
    cmd->add_option("--force-at", o->forceAt, "Point X,Y,Z (m): the force goes to the nearest node");
    cmd->add_option("--force", o->force, "Force FX,FY,FZ (N)");
    cmd->add_option("--force-until", o->forceUntil_s, "Release the force at this simulated time (s); default: never");
    cmd->add_option("--export-mesh", o->exportMesh, "Write the final deformed mesh (.txt, .obj or .ply)");
    cmd->add_option("--report", o->report, "Write a JSON report");
    cmd->add_option("--trajectory", o->trajectory,
                    "Drive the haptic loop with a device trajectory (CSV t,x,y,z,button)");
    cmd->add_option("--tool", o->tool,
                    "probe, scalpel (cuts above its threshold), a scene's tool or a tool file (with --trajectory)")
        ->capture_default_str();
    cmd->add_option("--device", o->devices,
                    "A device per hand: replay:FILE, openhaptics[:NAME] or sdl[:INDEX]; give it twice for two hands "
                    "(--trajectory counts as "
                    "the first). Live devices run in real time until --steps or Ctrl-C")
        ->expected(1)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    cmd->add_option("--second-tool", o->secondTool, "The second hand's tool")->capture_default_str();
    cmd->add_flag("--no-workspace-fit", o->noWorkspaceFit,
                  "Keep a device's own mapping (the scene's, or millimetres 1:1 round the model) instead of fitting "
                  "its reach to the model");
    cmd->add_option("--sdl-control", o->sdlControl, "A joystick's axes as position or rate (velocity)")
        ->capture_default_str();
    cmd->add_option("--hd-library", o->hdLibrary, "The OpenHaptics HD library to try first");
    cmd->add_flag("--realtime", o->realtime,
                  "Run the haptic loop at wall-clock rate in its own thread (with --trajectory)");
    cmd->add_option("--rate", o->rate_hz, "Haptic loop rate in Hz (with --trajectory)")
        ->capture_default_str()
        ->check(CLI::Range(100.0, 10'000.0));
    cmd->add_option("--force-log", o->forceLog, "Write every haptic step as CSV (with --trajectory)");
    cmd->add_option("--coupling-stiffness", o->couplingStiffness_N_per_m,
                    "Stiffness k_h of the proxy-device spring, N/m (with --trajectory)")
        ->capture_default_str()
        ->check(CLI::Range(1.0, 5000.0));
    cmd->add_option("--friction", o->friction,
                    "Static and dynamic friction coefficients 'S,D' of the proxy (with --trajectory); default none");
    cmd->add_option("--record", o->record,
                    "Write the device path with the rendered forces appended, replayable as a trajectory");
    cmd->add_option("--scene", o->scene,
                    "A scene file (TOML, see assets/scenes/heart.toml); options given here override it");
    cmd->add_option("--set", o->settings,
                    "KEY=VALUE: a scene key set over the scene's, spelt as in a scene file "
                    "(material.positioning_stiffness_N_per_m3=4.4e6, simulation.integrator=rk4); repeatable");
    cmd->callback([o, cmd] {
        o->stepsGiven = cmd->count("--steps") > 0;
        for (const CLI::Option* option : cmd->get_options())
            if (option->count() > 0) o->given.insert(option->get_name());
    });
    return [o] { return run(*o); };
}

}  // namespace hapticut::app
