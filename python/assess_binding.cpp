// hapticut.assess's C++ half: a session of a scene's exercise replayed and scored (scene/assessment),
// as the report `hapticut assess --report` writes.
#include <pybind11/pybind11.h>

#include <optional>
#include <string>

#include "hapticut/haptics/trajectory.h"
#include "hapticut/scene/assessment.h"
#include "hapticut/scene/assessment_report.h"
#include "raise_error.h"

namespace py = pybind11;

namespace hapticut::python {

namespace {

std::string assess(const std::string& sceneFile, const std::string& sessionFile) {
    std::optional<Result<nlohmann::ordered_json, Error>> report;
    {
        py::gil_scoped_release release;  // a session of a minute is a minute of simulated steps
        report.emplace([&]() -> Result<nlohmann::ordered_json, Error> {
            scene::SceneRequest request;
            request.file = sceneFile;
            auto scene = scene::loadScene(request);
            if (!scene) return unexpected(scene.error());
            auto session = haptics::readTrajectory(sessionFile);
            if (!session) return unexpected(session.error());
            auto assessed = scene::assess(*scene, *session, sessionFile);
            if (!assessed) return unexpected(assessed.error());
            return scene::assessmentReport(*assessed, sceneFile, sessionFile);
        }());
    }
    if (!*report) raiseError(report->error());
    nlohmann::ordered_json j;
    j["provenance"] = {{"hapticut", HAPTICUT_VERSION}, {"api", "python"}};
    for (const auto& [key, value] : report->value().items()) j[key] = value;
    return j.dump();
}

}  // namespace

void bindAssess(py::module_& module) { module.def("_assess", &assess, py::arg("scene"), py::arg("session")); }

}  // namespace hapticut::python
