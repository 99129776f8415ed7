// The Python module's C++ half (`hapticut._hapticut`): models as NumPy arrays that view the library's
// own arrays, reports as the command line's JSON, and the library's errors raised as
// hapticut.HapticutError with their file and line. The package's Python files wrap it (python/hapticut).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "hapticut/scene/model_info.h"
#include "hapticut/scene/model_source.h"
#include "raise_error.h"
#include "views.h"

namespace py = pybind11;

namespace hapticut::python {

[[noreturn]] void raiseError(const Error& error) {
    const py::object type = py::module_::import("hapticut.errors").attr("HapticutError");
    const py::object file = error.file.empty() ? py::object(py::none()) : py::object(py::str(error.file.string()));
    const py::object line = error.line > 0 ? py::object(py::int_(error.line)) : py::object(py::none());
    const py::object value = type(error.toString(), file, line, error.message);
    PyErr_SetObject(type.ptr(), value.ptr());
    throw py::error_already_set();
}

void bindSimulation(py::module_& module);
void bindRun(py::module_& module);
void bindBatch(py::module_& module);
void bindAssess(py::module_& module);

namespace {

/// A loaded model (or tool): what `hapticut info` reads, kept whole so NumPy can view into it.
struct Model {
    scene::ModelSource source;
};

Model load(const std::string& model, int triangles, const std::vector<std::string>& parts, double scale) {
    std::optional<Result<scene::ModelSource, Error>> loaded;
    {
        // Loading a large file or heart takes seconds that other Python threads can use.
        py::gil_scoped_release release;
        loaded.emplace(scene::loadModelSource(model, triangles, parts));
        if (*loaded) {
            if (scale != 1)
                for (Vec3& p : (*loaded)->mesh.positions) p *= scale;
            scene::describeInMetres(**loaded);
        }
    }
    if (!*loaded) raiseError(loaded->error());
    return Model{std::move(loaded->value())};
}

}  // namespace

PYBIND11_MODULE(_hapticut, module) {
    module.doc() = "Hapticut's C++ library; use the hapticut package, which wraps it";
    module.attr("__version__") = HAPTICUT_VERSION;

    py::class_<Model>(module, "Model", "A model or tool as loaded: rest positions, faces and named parts")
        .def_property_readonly(
            "name", [](const Model& m) { return m.source.name; }, "'heart' or the file it came from")
        .def_property_readonly(
            "positions",
            [](py::object self) {
                const auto& p = self.cast<const Model&>().source.mesh.positions;
                static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
                return readOnlyView(p.empty() ? nullptr : p.front().data(), p.size(), 3, sizeof(Vec3), self);
            },
            "(N, 3) float64 rest positions in metres, read-only, viewing the model's own array")
        .def_property_readonly(
            "faces",
            [](py::object self) {
                const auto& f = self.cast<const Model&>().source.mesh.faces;
                return readOnlyView(f.empty() ? nullptr : f.front().data(), f.size(), 3, sizeof(mesh::Face), self);
            },
            "(M, 3) uint32 vertex indices, counter-clockwise seen from outside, read-only")
        .def_property_readonly(
            "face_parts",
            [](py::object self) {
                const auto& m = self.cast<const Model&>().source.mesh;
                if (m.hasParts()) return readOnlyView(m.faceParts.data(), m.faceParts.size(), 0, 4, self);
                py::array_t<std::uint32_t> zeros(static_cast<py::ssize_t>(m.faces.size()));
                std::fill_n(zeros.mutable_data(), m.faces.size(), 0u);
                return py::array(zeros);
            },
            "(M,) uint32: the part of each face (an index into part_names); all zero for one part")
        .def_property_readonly(
            "file_vertices",
            [](const Model& m) {
                return fileVertices(m.source.vertexOrder.previousIndex, m.source.mesh.positions.size());
            },
            "(N,) uint32: each vertex's index in the file it came from. A file whose vertices came in no spatial "
            "order is renumbered in reverse Cuthill-McKee order when it loads, for speed; otherwise this is 0, 1, 2, "
            "...")
        .def_property_readonly(
            "part_names", [](const Model& m) { return m.source.mesh.partNames; },
            "the named parts (OBJ objects and groups, glTF and FBX meshes); empty for a model of one part")
        .def_property_readonly(
            "warnings",
            [](const Model& m) {
                std::vector<std::string> out;
                for (const Warning& w : m.source.warnings) out.push_back(w.toString());
                return out;
            },
            "what is unusual about the file but did not stop it loading")
        .def_property_readonly(
            "tool_threshold_N",
            [](const Model& m) { return m.source.toolThreshold_N ? py::cast(*m.source.toolThreshold_N) : py::none(); },
            "a tool file's cut threshold (N); None for a model");

    bindSimulation(module);
    bindRun(module);
    bindBatch(module);
    bindAssess(module);
    module.def("_load", &load, py::arg("model"), py::arg("triangles"), py::arg("parts"), py::arg("scale"));
    module.def(
        "_info_json",
        [](const std::string& model, int triangles, const std::vector<std::string>& parts, double scale) {
            const Model m = load(model, triangles, parts, scale);
            return scene::modelInfo(m.source).dump();
        },
        py::arg("model"), py::arg("triangles"), py::arg("parts"), py::arg("scale"));
}

}  // namespace hapticut::python
