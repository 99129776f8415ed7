// hapticut.Simulation: a scene's haptic loop driven step by step from Python, in simulated time. The
// script is the device: it gives the tool's position (and, when it knows its path, its velocity) each
// step and gets the force the hand would feel.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "arguments.h"
#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/scene/open_device.h"
#include "hapticut/scene/scene.h"
#include "raise_error.h"
#include "views.h"

namespace py = pybind11;

namespace hapticut::python {

namespace {

Vec3 toVec3(const py::object& value, const char* what) {
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || a.size() != 3) throw py::value_error(std::string(what) + " must be 3 numbers (x, y, z) in metres");
    const Vec3 v(a.at(0), a.at(1), a.at(2));
    if (!v.allFinite()) throw py::value_error(std::string(what) + " must be finite");
    return v;
}

py::array_t<double> toArray(const Vec3& v) {
    py::array_t<double> out(3);
    std::copy(v.data(), v.data() + 3, out.mutable_data());
    return out;
}

/// The positions array the views handed out so far look into, once a cut has moved the library's
/// array elsewhere: kept until the last of those views is gone.
struct RetiredPositions {
    std::vector<Vec3> array;
};

class Simulation {
public:
    Simulation(const std::string& sceneFile, const std::optional<std::string>& model, std::optional<int> triangles,
               const std::string& tool, const std::optional<std::string>& integrator, std::optional<double> rate_hz,
               const std::string& overlay) {
        scene::SceneRequest request;
        request.file = sceneFile;
        request.overlay = overlay;
        request.overrides.model = model;
        request.overrides.triangles = triangles;
        request.overrides.rate_hz = rate_hz;
        if (integrator) request.overrides.scheme = schemeArgument(*integrator);
        std::optional<Result<scene::Scene, Error>> loaded;
        {
            py::gil_scoped_release release;  // a large organ takes seconds to load
            loaded.emplace(scene::loadScene(request));
        }
        if (!*loaded) raiseError(loaded->error());
        scene_ = std::make_unique<scene::Scene>(std::move(loaded->value()));
        const auto tip = scene::toolTip(scene_->settings, tool);
        if (!tip) raiseError(tip.error());
        tool_ = tool;
        device_ = std::make_unique<haptics::VirtualDevice>(scene_->settings.maxForce_N);
        organ_ = std::make_unique<cutting::CutModel>(scene_->makeOrgan());
        organ_->keepRetiredPositions(true);  // .positions views the array; a cut must not free it under them
        const haptics::Hand hand = scene::makeHand(*scene_, *device_, *tip, nullptr);
        const haptics::LoopConfig config = scene::loopConfigFor(*scene_, *tip);
        std::optional<Result<std::unique_ptr<haptics::HapticLoop>, Error>> created;
        {
            py::gil_scoped_release release;  // and its collision tree and integrator seconds to prepare
            created.emplace(haptics::HapticLoop::create(*organ_, std::span<const haptics::Hand>(&hand, 1), config));
        }
        if (!*created) raiseError(created->error());
        loop_ = std::move(created->value());
        loop_->setRealtime(false);
    }

    py::array_t<double> step(const py::object& position, bool button, const py::object& velocity) {
        const Vec3 p = toVec3(position, "position");
        const std::uint32_t buttons = button ? 1u : 0u;
        if (velocity.is_none())
            device_->setPosition(p, buttons);
        else
            device_->setMotion(p, toVec3(velocity, "velocity"), buttons);
        {
            py::gil_scoped_release release;
            last_ = loop_->step();
        }
        ++steps_;
        keepViewedPositions();
        return toArray(last_.hand().force_N);
    }

    /// (N, 3) float64, read-only, over the library's own array: it follows every step with no copy. The
    /// nodes a cut adds appear in the next one taken; a view taken before a cut outgrew the array keeps
    /// the positions it last saw.
    static py::array positions(const py::object& self) {
        Simulation& s = self.cast<Simulation&>();
        const std::vector<Vec3>& p = s.organ_->model().nodes.position;
        if (!s.viewed_) s.viewed_ = std::make_shared<RetiredPositions>();
        // The base keeps both the simulation (whose array the view reads now) and the holder that will
        // take that array over if a cut moves it.
        auto* holder = new std::shared_ptr<RetiredPositions>(s.viewed_);
        const py::capsule retired(holder, [](void* h) { delete static_cast<std::shared_ptr<RetiredPositions>*>(h); });
        static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
        return readOnlyView(p.empty() ? nullptr : p.front().data(), p.size(), 3, sizeof(Vec3),
                            py::make_tuple(self, retired));
    }

    /// Writes the organ as it is now (deformed, cut, with its walls) to a .txt, .obj or .ply file.
    void exportMesh(const std::filesystem::path& file) const {
        mesh::SurfaceMesh deformed = organ_->mesh();
        deformed.positions = organ_->model().nodes.position;
        mesh::computeFaceNormals(deformed);
        if (const auto error = mesh::io::saveMesh(file, deformed, scene_->source.physics)) raiseError(*error);
    }

    /// The organ's faces now (cuts add some): a copy, since a cut may move the library's array.
    py::array_t<std::uint32_t> faces() const {
        const auto& faces = organ_->mesh().faces;
        py::array_t<std::uint32_t> out({static_cast<py::ssize_t>(faces.size()), py::ssize_t{3}});
        if (!faces.empty())
            std::copy(faces.front().data(), faces.front().data() + 3 * faces.size(), out.mutable_data());
        return out;
    }

    double time_s() const { return loop_->time_s(); }
    long steps() const { return steps_; }
    const haptics::HandStep& last() const { return last_.hand(); }
    const scene::Scene& scene() const { return *scene_; }
    const std::string& tool() const { return tool_; }
    const haptics::HapticLoop& loop() const { return *loop_; }

private:
    /// Hands an array a cut moved the positions out of to the views that look into it.
    void keepViewedPositions() {
        std::vector<std::vector<Vec3>> retired = organ_->takeRetiredPositions();
        if (retired.empty()) return;
        if (viewed_) viewed_->array = std::move(retired.front());  // later ones (one step, two moves) had no view
        viewed_.reset();
    }

    std::unique_ptr<scene::Scene> scene_;
    std::unique_ptr<haptics::VirtualDevice> device_;
    std::unique_ptr<cutting::CutModel> organ_;  // the loop holds it by reference: it must not move
    std::unique_ptr<haptics::HapticLoop> loop_;
    haptics::StepOutput last_;
    std::shared_ptr<RetiredPositions> viewed_;  // shared with every view of the current array
    std::string tool_;
    long steps_ = 0;
};

}  // namespace

void bindSimulation(py::module_& module) {
    py::class_<Simulation>(module, "Simulation",
                           "A scene's haptic loop stepped from Python in simulated time: the script is the device")
        .def(py::init<const std::string&, const std::optional<std::string>&, std::optional<int>, const std::string&,
                      const std::optional<std::string>&, std::optional<double>, const std::string&>(),
             py::arg("scene") = "", py::arg("model") = py::none(), py::arg("triangles") = py::none(),
             py::arg("tool") = "probe", py::arg("integrator") = py::none(), py::arg("rate_hz") = py::none(),
             py::arg("settings_toml") = "")
        .def("step", &Simulation::step, py::arg("position"), py::arg("button") = false,
             py::arg("velocity") = py::none(),
             "One haptic step (1 / rate_hz of simulated time) with the device at `position` (m); returns the "
             "force on the hand (N) as a NumPy array. `velocity` (m/s), when the script knows it, replaces the "
             "finite difference the loop's damping would otherwise use.")
        .def("export", &Simulation::exportMesh, py::arg("path"),
             "Write the organ as it is now, deformed and cut, to a .txt (thesis), .obj or .ply file")
        .def_property_readonly("positions", &Simulation::positions,
                               "(N, 3) float64: the nodes' positions now (m), a read-only view of the library's array "
                               "that follows every step; take it again after a cut for the nodes the cut added")
        .def_property_readonly("faces", &Simulation::faces,
                               "(M, 3) uint32: the organ's faces now, cuts and walls included (a copy)")
        .def_property_readonly(
            "file_vertices",
            [](const Simulation& s) {
                const scene::ModelSource& source = s.scene().source;
                return fileVertices(source.vertexOrder.previousIndex, source.mesh.positions.size());
            },
            "(N0,) uint32: for the N0 nodes the organ had when it loaded, each one's vertex index in the model file "
            "(a file in no spatial order is renumbered in reverse Cuthill-McKee order for speed; otherwise 0, 1, 2, "
            "...); "
            "the nodes cuts add come after them")
        .def_property_readonly("time_s", &Simulation::time_s, "simulated time so far (s)")
        .def_property_readonly("steps", &Simulation::steps, "steps taken")
        .def_property_readonly("rate_hz", [](const Simulation& s) { return s.loop().rate_hz(); })
        .def_property_readonly("tool", &Simulation::tool)
        .def_property_readonly("model", [](const Simulation& s) { return s.scene().source.name; })
        .def_property_readonly("integrator",
                               [](const Simulation& s) { return std::string(physics::schemeName(s.loop().scheme())); })
        .def_property_readonly(
            "proxy", [](const Simulation& s) { return toArray(s.last().proxy_m); },
            "the proxy (the tool's tip held on the surface) after the last step (m)")
        .def_property_readonly("contact", [](const Simulation& s) { return s.last().contact; })
        .def_property_readonly(
            "cutting", [](const Simulation& s) { return s.last().cutting; },
            "the blade pressed into uncut tissue at the end of its cut in the last step")
        .def_property_readonly(
            "cut_stats",
            [](const Simulation& s) {
                const cutting::CutStats& c = s.loop().cutter().stats();
                py::dict d;
                d["cuts"] = c.cuts;
                d["cut_points"] = c.cutPoints;
                d["vertices_added"] = c.verticesAdded;
                d["faces_added"] = c.facesAdded;
                d["joins"] = c.joins;
                d["wounds_crossed"] = c.woundsCrossed;
                d["openings"] = c.openings;
                d["walls_closed"] = c.wallsClosed;
                d["cut_length_m"] = c.length_m;
                d["opened"] = c.opened;
                return d;
            },
            "what the tool has cut so far, with the run report's names");
}

}  // namespace hapticut::python
