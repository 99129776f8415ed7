// hapticut.run's C++ half: a scene's replayed trajectories through the haptic loop in simulated time,
// as `hapticut run` does it, giving the same report (scene/run_report) and force log.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "arguments.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/step_log.h"
#include "hapticut/scene/haptic_run.h"
#include "hapticut/scene/open_device.h"
#include "hapticut/scene/run_report.h"
#include "hapticut/scene/scene.h"
#include "raise_error.h"

namespace py = pybind11;

namespace hapticut::python {

namespace {

struct RunArguments {
    std::string scene, overlay;
    std::optional<std::string> model, trajectory, tool, integrator;
    std::optional<int> triangles;
    std::optional<long> steps;
    std::optional<double> rate_hz;
};

/// (report as JSON text, force log as CSV text): the text the command line would write.
std::pair<std::string, std::string> run(const RunArguments& a) {
    scene::SceneRequest request;
    request.file = a.scene;
    request.overlay = a.overlay;
    request.overrides.model = a.model;
    request.overrides.triangles = a.triangles;
    request.overrides.rate_hz = a.rate_hz;
    request.overrides.trajectory = a.trajectory;
    if (a.integrator) request.overrides.scheme = schemeArgument(*a.integrator);
    if (a.steps && *a.steps < 1) throw py::value_error("steps must be at least 1");
    std::optional<Result<scene::Scene, Error>> loaded;
    {
        py::gil_scoped_release release;
        loaded.emplace(scene::loadScene(request));
    }
    if (!*loaded) raiseError(loaded->error());
    const scene::Scene& scene = loaded->value();

    // The hands: the trajectory (given, or the scene's replay device), else the scene's [[devices]],
    // each of which must be a replay: a script's run is in simulated time.
    std::vector<haptics::DeviceName> specs;
    std::vector<const scene::SceneDevice*> fromScene;
    const std::string trajectory = scene.settings.deviceBackend == "replay" ? scene.settings.trajectory : "";
    if (!trajectory.empty()) {
        specs.push_back({haptics::DeviceKind::Replay, trajectory});
        fromScene.push_back(nullptr);
    } else {
        for (const scene::SceneDevice& d : scene.settings.devices) {
            if (d.device.kind != haptics::DeviceKind::Replay)
                throw py::value_error("the scene's device " + d.device.toString() +
                                      " is live: hapticut.run replays trajectories in simulated time (give "
                                      "trajectory=, or drive hapticut.Simulation from the device yourself)");
            specs.push_back(d.device);
            fromScene.push_back(&d);
        }
    }
    if (specs.empty()) throw py::value_error("nothing to replay: give trajectory= or a scene whose devices replay");

    cutting::CutModel organ = scene.makeOrgan();
    std::vector<scene::OpenedDevice> opened;
    std::vector<haptics::Hand> hands;
    scene::HapticRunRequest report;
    double duration_s = 0;
    for (std::size_t h = 0; h < specs.size(); ++h) {
        const std::string tool = h == 0 && a.tool                              ? *a.tool
                                 : fromScene[h] && !fromScene[h]->tool.empty() ? fromScene[h]->tool
                                                                               : std::string("probe");
        const auto tip = scene::toolTip(scene.settings, tool);
        if (!tip) raiseError(tip.error());
        const scene::DeviceOptions options =
            fromScene[h] ? scene::deviceOptionsFor(*fromScene[h], true, "") : scene::DeviceOptions{};
        auto device = scene::openDeviceFor(scene, specs[h], options);
        if (!device) raiseError(device.error());
        if (const auto* replay = dynamic_cast<const haptics::ReplayDevice*>(device->device.get()))
            duration_s = std::max(duration_s, replay->trajectory().duration_s());
        hands.push_back(scene::makeHand(scene, *device->device, *tip, fromScene[h]));
        report.hands.push_back({specs[h].toString(), device->description, tool, *tip});
        opened.push_back(std::move(*device));
    }

    scene::HapticRunConfig config;
    config.loop = scene::loopConfigFor(scene, report.hands[0].tip);
    config.steps = a.steps ? *a.steps : std::lround(duration_s * scene.settings.rate_hz) + 1;
    config.keepSteps = config.steps;
    config.tool = report.hands[0].tool;
    config.stopRequested = [] { return false; };
    std::optional<Result<scene::HapticRunResult, Error>> result;
    {
        py::gil_scoped_release release;
        result.emplace(scene::runHaptic(organ, hands, config));
    }
    if (!*result) raiseError(result->error());
    const scene::HapticRunResult& r = result->value();

    report.requestedScheme = scene.settings.scheme;
    report.rate_hz = scene.settings.rate_hz;
    report.tool = report.hands[0].tool;
    report.trajectory = trajectory;
    report.stepsRequested = config.steps;
    nlohmann::ordered_json j;
    j["provenance"] = {{"hapticut", HAPTICUT_VERSION}, {"api", "python"}};
    const nlohmann::ordered_json body = scene::hapticRunReport(scene.source, organ, config.loop, report, r);
    for (const auto& [key, value] : body.items()) j[key] = value;
    return {j.dump(), haptics::formatStepLog(r.keptSteps, haptics::StepLogColumns::ForceLog)};
}

}  // namespace

void bindRun(py::module_& module) {
    module.def(
        "_run",
        [](const std::string& scene, const std::string& overlay, const std::optional<std::string>& model,
           std::optional<int> triangles, const std::optional<std::string>& trajectory,
           const std::optional<std::string>& tool, std::optional<long> steps,
           const std::optional<std::string>& integrator, std::optional<double> rate_hz) {
            return run({scene, overlay, model, trajectory, tool, integrator, triangles, steps, rate_hz});
        },
        py::arg("scene"), py::arg("overlay"), py::arg("model"), py::arg("triangles"), py::arg("trajectory"),
        py::arg("tool"), py::arg("steps"), py::arg("integrator"), py::arg("rate_hz"));
}

}  // namespace hapticut::python
