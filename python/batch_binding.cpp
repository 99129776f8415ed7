// hapticut.batch's C++ half: a spec read and checked by the library (scene/batch_spec), as JSON.
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "hapticut/scene/batch_spec.h"
#include "raise_error.h"

namespace py = pybind11;

namespace hapticut::python {

namespace {

template <class T>
nlohmann::json orNull(const std::optional<T>& value) {
    return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

std::string batchSpec(const std::string& file) {
    std::optional<Result<scene::BatchSpec, Error>> read;
    {
        py::gil_scoped_release release;  // checking every swept value reads the scene each time
        read.emplace(scene::readBatchSpec(file));
    }
    if (!*read) raiseError(read->error());
    const scene::BatchSpec& spec = read->value();
    nlohmann::ordered_json j;
    j["file"] = spec.file.string();
    j["scene"] = spec.scene.empty() ? nlohmann::json(nullptr) : nlohmann::json(spec.scene.string());
    j["model"] = orNull(spec.model);
    j["triangles"] = orNull(spec.triangles);
    j["tool"] = orNull(spec.tool);
    j["steps"] = orNull(spec.steps);
    j["integrator"] = orNull(spec.integrator);
    j["rate_hz"] = orNull(spec.rate_hz);
    j["sessions"] = nlohmann::json::array();
    for (const auto& s : spec.sessions) j["sessions"].push_back(s.string());
    j["sessions_from_folder"] = spec.sessionsFromFolder;
    j["sweep"] = nlohmann::json::array();
    for (const scene::SweepAxis& axis : spec.sweep)
        j["sweep"].push_back({{"key", axis.key}, {"line", axis.line}, {"values", axis.values}});
    return j.dump();
}

}  // namespace

void bindBatch(py::module_& module) { module.def("_batch_spec", &batchSpec, py::arg("file")); }

}  // namespace hapticut::python
