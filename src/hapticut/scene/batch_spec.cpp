// Reads a batch spec with toml++, keeping each key's line for its errors.
#include "hapticut/scene/batch_spec.h"

#include <toml++/toml.h>

#include <algorithm>
#include <set>
#include <sstream>

#include "hapticut/common/text_file.h"
#include "hapticut/physics/scheme.h"
#include "hapticut/scene/scene.h"
#include "hapticut/scene/scene_file.h"

namespace hapticut::scene {

namespace {

struct SpecError {
    int line;
    std::string message;
};

int specLine(const toml::node& node) { return static_cast<int>(node.source().begin.line); }

template <class T>
T expect(const toml::node& node, const std::string& key, const char* what) {
    const std::optional<T> value = node.value<T>();
    if (!value) throw SpecError{specLine(node), "batch." + key + " must be " + what};
    return *value;
}

/// A path the spec gives, relative to the spec's folder, which must exist.
std::filesystem::path existingPath(const toml::node& node, const std::string& key, const std::filesystem::path& folder,
                                   bool directory) {
    const std::filesystem::path given = expect<std::string>(node, key, "text, a path");
    const std::filesystem::path path = given.is_absolute() ? given : folder / given;
    std::error_code error;
    const bool found =
        directory ? std::filesystem::is_directory(path, error) : std::filesystem::is_regular_file(path, error);
    if (!found)
        throw SpecError{specLine(node), "batch." + key + ": " + (directory ? "no folder " : "no file ") +
                                            path.string() +
                                            (given.is_absolute() ? "" : " (paths are relative to the spec's folder)")};
    return path;
}

std::string tomlText(const toml::node& value) {
    std::ostringstream out;
    value.visit([&](const auto& v) { out << v; });
    return out.str();
}

void readBatchTable(const toml::table& batch, const std::filesystem::path& folder, BatchSpec& spec) {
    static const std::set<std::string> keys{"scene", "model", "triangles",  "trajectory", "sessions",
                                            "tool",  "steps", "integrator", "rate_hz"};
    for (const auto& [name, node] : batch) {
        const std::string key(name.str());
        if (key == "scene")
            spec.scene = existingPath(node, key, folder, false);
        else if (key == "model") {
            const std::string model = expect<std::string>(node, key, "\"heart\" or a model file");
            spec.model = model == "heart" ? model : existingPath(node, key, folder, false).string();
        } else if (key == "triangles")
            spec.triangles = static_cast<int>(expect<std::int64_t>(node, key, "a whole number of triangles"));
        else if (key == "trajectory")
            spec.sessions = {existingPath(node, key, folder, false)};
        else if (key == "sessions") {
            const std::filesystem::path dir = existingPath(node, key, folder, true);
            for (const auto& entry : std::filesystem::directory_iterator(dir))
                if (entry.is_regular_file() && entry.path().extension() == ".csv")
                    spec.sessions.push_back(entry.path());
            std::sort(spec.sessions.begin(), spec.sessions.end());
            if (spec.sessions.empty())
                throw SpecError{specLine(node),
                                "batch.sessions: " + dir.string() + " holds no recorded session (.csv)"};
            spec.sessionsFromFolder = true;
        } else if (key == "tool")
            spec.tool = expect<std::string>(node, key, "a tool's name"), spec.toolLine = specLine(node);
        else if (key == "steps") {
            spec.steps = expect<std::int64_t>(node, key, "a whole number of steps");
            if (*spec.steps < 1) throw SpecError{specLine(node), "batch.steps must be at least 1"};
        } else if (key == "integrator") {
            spec.integrator = expect<std::string>(node, key, "an integrator's name");
            if (!physics::parseScheme(*spec.integrator))
                throw SpecError{specLine(node), "batch.integrator: '" + *spec.integrator +
                                                    "' is none of auto, euler, midpoint, rk4, symplectic, implicit"};
        } else if (key == "rate_hz")
            spec.rate_hz = expect<double>(node, key, "a number of steps a second");
        else {
            std::string allowed;
            for (const std::string& k : keys) allowed += (allowed.empty() ? "" : ", ") + k;
            throw SpecError{specLine(node), "batch." + key + " is not a batch key (allowed: " + allowed + ")"};
        }
    }
    if (batch.contains("trajectory") && batch.contains("sessions"))
        throw SpecError{specLine(*batch.get("sessions")), "batch: give trajectory or sessions, not both"};
}

void readSweep(const toml::table& sweep, BatchSpec& spec) {
    for (const auto& [name, node] : sweep) {
        const std::string key(name.str());
        const toml::array* values = node.as_array();
        if (!values || values->empty())
            throw SpecError{specLine(node),
                            "sweep \"" + key + "\" must be a list of the values to try, such as [1, 2]"};
        SweepAxis axis{key, specLine(node), {}};
        for (const toml::node& value : *values) axis.values.push_back(tomlText(value));
        spec.sweep.push_back(std::move(axis));
    }
    std::sort(spec.sweep.begin(), spec.sweep.end(),
              [](const SweepAxis& a, const SweepAxis& b) { return a.line < b.line; });
}

/// Lays each swept value over the base scene and checks it as a scene file's key, and the tool by name.
std::optional<Error> checkAgainstScene(const BatchSpec& spec) {
    SceneRequest request;
    request.file = spec.scene;
    request.overrides.model = spec.model;
    request.overrides.triangles = spec.triangles;
    request.overrides.rate_hz = spec.rate_hz;
    const auto base = sceneSettings(request);
    if (!base) return base.error();
    if (spec.tool)
        if (const auto tip = toolTip(*base, *spec.tool); !tip)
            return Error{spec.file, spec.toolLine, "batch.tool: " + tip.error().toString()};
    for (const SweepAxis& axis : spec.sweep)
        for (const std::string& value : axis.values) {
            request.overlay = axis.key + " = " + value + "\n";
            const auto settings = sceneSettings(request);
            if (!settings) {
                const Error& e = settings.error();
                if (e.file != kOverlayName) return e;  // the scene file's own mistake, at its own line
                return Error{spec.file, axis.line, "sweep \"" + axis.key + "\" = " + value + ": " + e.message};
            }
        }
    return std::nullopt;
}

}  // namespace

Result<BatchSpec, Error> readBatchSpec(const std::filesystem::path& file) {
    const auto text = readTextFile(file, std::size_t{1} << 20);
    if (!text) return unexpected(text.error());
    BatchSpec spec;
    spec.file = file;
    try {
        const toml::table root = toml::parse(*text, file.string());
        for (const auto& [name, node] : root)
            if (name != "batch" && name != "sweep")
                throw SpecError{specLine(node),
                                "'" + std::string(name.str()) + "': a spec has [batch] and [sweep] only"};
        const toml::table* batch = root["batch"].as_table();
        if (!batch) throw SpecError{1, "no [batch] table: it names the scene or model and what each run replays"};
        readBatchTable(*batch, file.parent_path(), spec);
        if (const toml::table* sweep = root["sweep"].as_table())
            readSweep(*sweep, spec);
        else if (root.contains("sweep"))
            throw SpecError{specLine(*root.get("sweep")), "sweep must be a table of lists"};
    } catch (const toml::parse_error& e) {
        return unexpected(Error{file, static_cast<int>(e.source().begin.line), std::string(e.description())});
    } catch (const SpecError& e) {
        return unexpected(Error{file, e.line, e.message});
    }
    if (auto error = checkAgainstScene(spec)) return unexpected(std::move(*error));
    return spec;
}

}  // namespace hapticut::scene
