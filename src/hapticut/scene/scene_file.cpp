// Scene files (TOML) with strict checking of keys, types and ranges.
#include "hapticut/scene/scene_file.h"

#include "hapticut/common/line_reader.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>

#include "hapticut/geometry/aabb.h"
#include "hapticut/mesh/procedural/tools.h"

namespace hapticut::scene {

namespace {

struct SceneError {
    int line;
    std::string message;
};

/// The node's line; negative for a line of the overlay, so that its errors name the overlay, not the file.
int lineOf(const toml::node& node) {
    const int line = static_cast<int>(node.source().begin.line);
    const auto& path = node.source().path;
    return path && *path == kOverlayName ? -line : line;
}

std::string join(const std::set<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

/// Refuses keys the table should not have, naming the allowed ones.
void allowOnly(const toml::table& table, const std::string& path, const std::set<std::string>& allowed) {
    for (const auto& [key, node] : table)
        if (!allowed.count(std::string(key.str())))
            throw SceneError{lineOf(node), (path.empty() ? "" : path + ".") + std::string(key.str()) +
                                               ": unknown key; allowed here: " + join(allowed)};
}

const toml::table* subTable(const toml::table& root, const std::string& name) {
    const toml::node* node = root.get(name);
    if (!node) return nullptr;
    if (!node->is_table()) throw SceneError{lineOf(*node), name + ": expected a table [" + name + "]"};
    return node->as_table();
}

/// A number as a user wrote it: whole ones in full (20000000, not 2e+07), others with the digits that
/// tell them apart (20000000.9).
std::string shown(double v) {
    return v == std::floor(v) && std::abs(v) < 1e15 ? std::to_string(static_cast<long long>(v)) : formatDouble(v);
}

double number(const toml::table& t, const std::string& path, const std::string& key, double fallback, double lo,
              double hi) {
    const toml::node* node = t.get(key);
    if (!node) return fallback;
    const auto v = node->value<double>();
    if (!v || !(node->is_floating_point() || node->is_integer()))
        throw SceneError{lineOf(*node), path + "." + key + ": expected a number"};
    if (!std::isfinite(*v) || *v < lo || *v > hi)  // shortest round-trip digits: 20000000.9 is not 2e+07
        throw SceneError{lineOf(*node), path + "." + key + ": " + shown(*v) +
                                            " is out of range; allowed: " + shown(lo) + " to " + shown(hi)};
    return *v;
}

/// A count: a number as number() takes it, and whole.
long wholeNumber(const toml::table& t, const std::string& path, const std::string& key, long fallback, long lo,
                 long hi) {
    const double v =
        number(t, path, key, static_cast<double>(fallback), static_cast<double>(lo), static_cast<double>(hi));
    if (v != std::floor(v))
        throw SceneError{lineOf(*t.get(key)), path + "." + key + ": expected a whole number, found " + shown(v)};
    return static_cast<long>(v);
}

bool boolean(const toml::table& t, const std::string& path, const std::string& key, bool fallback) {
    const toml::node* node = t.get(key);
    if (!node) return fallback;
    if (!node->is_boolean()) throw SceneError{lineOf(*node), path + "." + key + ": expected true or false"};
    return *node->value<bool>();
}

std::string text(const toml::table& t, const std::string& path, const std::string& key, const std::string& fallback,
                 const std::set<std::string>& choices = {}) {
    const toml::node* node = t.get(key);
    if (!node) return fallback;
    if (!node->is_string()) throw SceneError{lineOf(*node), path + "." + key + ": expected a string"};
    std::string v = *node->value<std::string>();
    if (!choices.empty() && !choices.count(v))
        throw SceneError{lineOf(*node), path + "." + key + ": '" + v + "' is not allowed; allowed: " + join(choices)};
    return v;
}

/// An array of strings; empty when the key is absent.
std::vector<std::string> strings(const toml::table& t, const std::string& path, const std::string& key) {
    const toml::node* node = t.get(key);
    if (!node) return {};
    const toml::array* a = node->as_array();
    if (!a) throw SceneError{lineOf(*node), path + "." + key + ": expected an array of strings"};
    std::vector<std::string> out;
    for (const toml::node& item : *a) {
        if (!item.is_string()) throw SceneError{lineOf(item), path + "." + key + ": expected an array of strings"};
        out.push_back(*item.value<std::string>());
    }
    return out;
}

Vec3 vector3(const toml::table& t, const std::string& path, const std::string& key, const Vec3& fallback,
             double limit) {
    const toml::node* node = t.get(key);
    if (!node) return fallback;
    const toml::array* a = node->as_array();
    if (!a || a->size() != 3) throw SceneError{lineOf(*node), path + "." + key + ": expected three numbers [x, y, z]"};
    Vec3 v;
    for (std::size_t k = 0; k < 3; ++k) {
        const auto x = (*a)[k].value<double>();
        if (!x || !std::isfinite(*x) || std::abs(*x) > limit)
            throw SceneError{lineOf(*node), path + "." + key + ": expected three finite numbers within ±" +
                                                std::to_string(static_cast<long long>(limit))};
        v[static_cast<Eigen::Index>(k)] = *x;
    }
    return v;
}

std::string resolve(const std::string& name, const std::filesystem::path& directory) {
    if (name.empty() || name == "heart") return name;
    const std::filesystem::path p(name);
    return p.is_absolute() ? name : (directory / p).lexically_normal().string();
}

Eigen::Quaterniond rotationFromDegrees(const Vec3& deg) {
    const Vec3 r = deg * std::numbers::pi / 180;
    return Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
           Eigen::AngleAxisd(r.x(), Vec3::UnitX());
}

/// One [[regions]] table.
SceneRegion parseRegion(const toml::node& node, std::size_t index, const std::filesystem::path& directory) {
    const std::string path = "regions[" + std::to_string(index) + "]";
    const toml::table* t = node.as_table();
    if (!t) throw SceneError{lineOf(node), path + ": expected a table"};
    allowOnly(*t, path,
              {"shape", "center_m", "radius_m", "size_m", "mesh", "stiffness_scale", "damping_scale", "toughness_scale",
               "hidden"});
    SceneRegion r;
    r.line = lineOf(*t);
    const std::string shape = text(*t, path, "shape", t->contains("mesh") ? "mesh" : "", {"sphere", "box", "mesh"});
    if (shape.empty()) throw SceneError{r.line, path + ": needs a shape (sphere, box) or a mesh"};
    const auto need = [&](const char* key) {
        if (!t->contains(key)) throw SceneError{r.line, path + ": a " + shape + " needs " + key};
    };
    const auto refuse = [&](const char* key) {
        if (const toml::node* n = t->get(key))
            throw SceneError{lineOf(*n), path + "." + key + ": a " + shape + " has none"};
    };
    if (shape == "sphere") {
        r.shape = SceneRegion::Shape::Sphere;
        need("center_m"), need("radius_m"), refuse("size_m"), refuse("mesh");
        r.center_m = vector3(*t, path, "center_m", Vec3::Zero(), 100);
        r.radius_m = number(*t, path, "radius_m", 0, 1e-6, 100);
    } else if (shape == "box") {
        r.shape = SceneRegion::Shape::Box;
        need("center_m"), need("size_m"), refuse("radius_m"), refuse("mesh");
        r.center_m = vector3(*t, path, "center_m", Vec3::Zero(), 100);
        r.size_m = vector3(*t, path, "size_m", Vec3::Zero(), 100);
        if ((r.size_m.array() <= 0).any())
            throw SceneError{lineOf(*t->get("size_m")), path + ".size_m: expected three sizes above 0"};
    } else {
        r.shape = SceneRegion::Shape::Mesh;
        need("mesh"), refuse("center_m"), refuse("radius_m"), refuse("size_m");
        r.mesh = resolve(text(*t, path, "mesh", ""), directory);
    }
    r.stiffnessScale = number(*t, path, "stiffness_scale", 1, 0.01, 1000);
    r.dampingScale = number(*t, path, "damping_scale", 1, 0.01, 1000);
    r.toughnessScale = number(*t, path, "toughness_scale", 1, 0.01, 1000);
    r.hidden = boolean(*t, path, "hidden", false);
    return r;
}

/// The [exercise] table; the scene's regions and tools are already read.
SceneExercise parseExercise(const toml::table& t, const SceneFile& s) {
    const std::string path = "exercise";
    allowOnly(
        t, path,
        {"kind", "instructions", "time_limit_s", "tool", "path_m", "corridor_m", "depth_m", "radius_m", "max_force_N"});
    SceneExercise e;
    e.line = lineOf(t);
    const std::string kind = text(t, path, "kind", "", {"incision", "palpation"});
    if (kind.empty()) throw SceneError{e.line, "exercise.kind: every exercise needs one: incision or palpation"};
    e.kind = kind == "incision" ? SceneExercise::Kind::Incision : SceneExercise::Kind::Palpation;
    const auto refuse = [&](const char* key) {
        if (const toml::node* n = t.get(key))
            throw SceneError{lineOf(*n),
                             path + "." + key + ": " + (kind == "incision" ? "an " : "a ") + kind + " has none"};
    };
    e.instructions = text(t, path, "instructions", "");
    e.timeLimit_s = number(t, path, "time_limit_s", 0, 0, 24 * 3600);
    e.tool = text(t, path, "tool", "");
    if (!e.tool.empty()) {
        std::set<std::string> names;
        for (const SceneTool& tool : s.tools) names.insert(tool.name);
        if (!names.count(e.tool))
            throw SceneError{lineOf(*t.get("tool")),
                             path + ".tool: '" + e.tool + "' is not one of the scene's tools: " + join(names)};
    }
    e.maxForce_N = number(t, path, "max_force_N", e.maxForce_N, 0.01, 50);
    if (e.kind == SceneExercise::Kind::Incision) {
        refuse("radius_m");
        const toml::node* points = t.get("path_m");
        if (!points) throw SceneError{e.line, "exercise.path_m: an incision needs its target line's points"};
        const toml::array* list = points->as_array();
        if (!list || list->size() < 2)
            throw SceneError{lineOf(*points), "exercise.path_m: expected two or more points [[x, y, z], ...]"};
        for (std::size_t i = 0; i < list->size(); ++i) {
            const std::string at = "exercise.path_m[" + std::to_string(i) + "]";
            const toml::array* p = (*list)[i].as_array();
            Vec3 v;
            for (Eigen::Index k = 0; p && p->size() == 3 && k < 3; ++k) {
                const auto x = (*p)[static_cast<std::size_t>(k)].value<double>();
                if (!x || !std::isfinite(*x) || std::abs(*x) > 100)
                    p = nullptr;
                else
                    v[k] = *x;
            }
            if (!p || p->size() != 3)
                throw SceneError{lineOf((*list)[i]), at + ": expected three finite numbers [x, y, z] within ±100"};
            if (!e.path_m.empty() && (v - e.path_m.back()).norm() < 1e-6)
                throw SceneError{lineOf((*list)[i]), at + ": the same point as the one before it"};
            e.path_m.push_back(v);
            e.pathLines.push_back(lineOf((*list)[i]));
        }
        e.corridor_m = number(t, path, "corridor_m", e.corridor_m, 1e-5, 0.1);
        e.depth_m = number(t, path, "depth_m", e.depth_m, 1e-4, 0.1);
    } else {
        refuse("path_m"), refuse("corridor_m"), refuse("depth_m");
        e.radius_m = number(t, path, "radius_m", e.radius_m, 1e-4, 0.1);
        if (std::none_of(s.regions.begin(), s.regions.end(), [](const SceneRegion& r) { return r.hidden; }))
            throw SceneError{e.line,
                             "exercise: a palpation needs a lump to find: a [[regions]] table with hidden = true"};
    }
    return e;
}

/// One [[devices]] table; the scene's tools are already read.
SceneDevice parseDevice(const toml::node& node, std::size_t index, const SceneFile& s,
                        const std::filesystem::path& directory) {
    const std::string path = "devices[" + std::to_string(index) + "]";
    const toml::table* t = node.as_table();
    if (!t) throw SceneError{lineOf(node), path + ": expected a table"};
    allowOnly(*t, path,
              {"device", "tool", "stiffness_N_per_m", "damping_Ns_per_m", "max_force_N", "max_force_rate_N_per_s",
               "workspace", "workspace_scale", "workspace_offset_m", "workspace_rotate_deg", "sdl_control"});
    SceneDevice d;
    d.line = lineOf(*t);
    const std::string name = text(*t, path, "device", "");
    if (name.empty())
        throw SceneError{
            lineOf(*t),
            path + ".device: every device needs a name: virtual, replay:FILE, openhaptics[:NAME] or sdl[:INDEX]"};
    auto parsed = haptics::parseDeviceName(name);
    if (!parsed) throw SceneError{lineOf(*t->get("device")), path + ".device: " + parsed.error().message};
    d.device = *parsed;
    if (d.device.kind == haptics::DeviceKind::Replay) d.device.argument = resolve(d.device.argument, directory);
    d.tool = text(*t, path, "tool", "");
    if (!d.tool.empty()) {
        bool known = false;
        std::set<std::string> names;
        for (const SceneTool& tool : s.tools) known = known || tool.name == d.tool, names.insert(tool.name);
        if (!known)
            throw SceneError{lineOf(*t->get("tool")),
                             path + ".tool: '" + d.tool + "' is not one of the scene's tools: " + join(names)};
    }
    if (t->get("stiffness_N_per_m")) d.couplingStiffness_N_per_m = number(*t, path, "stiffness_N_per_m", 400, 1, 5000);
    if (t->get("damping_Ns_per_m")) d.couplingDamping_Ns_per_m = number(*t, path, "damping_Ns_per_m", 0.3, 0, 100);
    d.maxForce_N = number(*t, path, "max_force_N", d.maxForce_N, 0, 50);
    d.maxForceRate_N_per_s = number(*t, path, "max_force_rate_N_per_s", d.maxForceRate_N_per_s, 1, 1e6);
    d.fitWorkspace = text(*t, path, "workspace", "fit", {"fit", "mapped"}) == "fit";
    d.workspace.scale = number(*t, path, "workspace_scale", 1, 1e-6, 1e6);
    d.workspace.offset_m = vector3(*t, path, "workspace_offset_m", Vec3::Zero(), 100);
    d.workspace.rotation = rotationFromDegrees(vector3(*t, path, "workspace_rotate_deg", Vec3::Zero(), 3600));
    d.sdlControl = text(*t, path, "sdl_control", d.sdlControl, {"position", "rate"});
    return d;
}

/// Keys with more dotted parts than this are refused before parsing: toml++ recurses once per part of a
/// dotted key or table header, so a header 100,000 parts long overflows the stack. A scene needs three.
constexpr int kMaxKeyParts = 64;

/// The first line whose key (before '=') or table header has more than kMaxKeyParts parts, and how many.
std::optional<std::pair<int, int>> overlyDottedKey(std::string_view text) {
    int line = 1;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        const std::string_view l = text.substr(start, end - start);
        const std::size_t first = l.find_first_not_of(" \t");
        const bool header = first != std::string_view::npos && l[first] == '[';
        int parts = 1;
        char quote = 0;
        for (std::size_t i = first == std::string_view::npos ? l.size() : first; i < l.size(); ++i) {
            const char c = l[i];
            if (quote) {
                if (c == quote)
                    quote = 0;
                else if (c == '\\' && quote == '"')
                    ++i;
            } else if (c == '"' || c == '\'') {
                quote = c;
            } else if (c == '#' || (header && c == ']') || (!header && c == '=')) {
                break;
            } else if (c == '.') {
                ++parts;
            }
        }
        if (parts > kMaxKeyParts) return std::pair{line, parts};
        start = end + 1;
        ++line;
    }
    return std::nullopt;
}

/// Sets every key of `overlay` in `root`: a table into the table of that name, anything else in place.
/// Moved, not copied: a copied node forgets where it came from, and errors name the overlay's lines.
void mergeInto(toml::table& root, toml::table&& overlay) {
    for (auto&& [key, value] : overlay) {
        toml::node* existing = root.get(key);
        if (existing && existing->is_table() && value.is_table())
            mergeInto(*existing->as_table(), std::move(*value.as_table()));
        else
            root.insert_or_assign(key, std::move(value));
    }
}

}  // namespace

SceneFile defaultScene() {
    SceneFile s;
    s.tools = {{"probe", "", mesh::procedural::kProbeThreshold_N, mesh::procedural::kProbeTipRadius_m},
               {"scalpel", "", mesh::procedural::kScalpelThreshold_N, mesh::procedural::kScalpelTipRadius_m}};
    return s;
}

Result<SceneFile, Error> parseScene(std::string_view source, const std::filesystem::path& file,
                                    const std::filesystem::path& directory, std::string_view overlay) {
    for (const auto& [text, name] : {std::pair{source, file}, {overlay, std::filesystem::path(kOverlayName)}})
        if (const auto deep = overlyDottedKey(text))
            return unexpected(Error{name, deep->first,
                                    "a key of " + std::to_string(deep->second) + " dotted parts; at most " +
                                        std::to_string(kMaxKeyParts) + " (a scene's keys have at most 3)"});
    toml::table root;
    try {
        root = toml::parse(source, file.string());
    } catch (const toml::parse_error& e) {
        return unexpected(Error{file, static_cast<int>(e.source().begin.line), std::string(e.description())});
    }
    if (!overlay.empty()) {
        try {
            mergeInto(root, toml::parse(overlay, std::string(kOverlayName)));
        } catch (const toml::parse_error& e) {
            return unexpected(
                Error{kOverlayName, static_cast<int>(e.source().begin.line), std::string(e.description())});
        }
    }
    try {
        SceneFile s = defaultScene();
        allowOnly(
            root, "",
            {"model", "material", "regions", "tools", "device", "devices", "simulation", "rendering", "exercise"});
        if (const toml::table* m = subTable(root, "model")) {
            allowOnly(*m, "model",
                      {"source", "triangles", "translate_m", "rotate_deg", "scale", "center", "fit_size_m", "parts"});
            s.model = resolve(text(*m, "model", "source", s.model), directory);
            s.triangles = static_cast<int>(wholeNumber(*m, "model", "triangles", s.triangles, 12, 20'000'000));
            s.translate_m = vector3(*m, "model", "translate_m", s.translate_m, 100);
            s.rotate_deg = vector3(*m, "model", "rotate_deg", s.rotate_deg, 3600);
            s.scale = number(*m, "model", "scale", s.scale, 1e-6, 1e6);
            s.center = boolean(*m, "model", "center", s.center);
            if (m->contains("fit_size_m")) s.fitSize_m = number(*m, "model", "fit_size_m", 0.1, 1e-4, 100);
            s.parts = strings(*m, "model", "parts");
        }
        if (const toml::table* m = subTable(root, "material")) {
            allowOnly(*m, "material",
                      {"mass_kg", "structural_stiffness_N", "structural_damping_Ns", "positioning_stiffness_N_per_m3",
                       "positioning_damping_Ns_per_m3", "toughness_J_per_m2", "bulk_modulus_Pa", "strain_limit"});
            physics::Material& mat = s.material;
            mat.totalMass_kg = number(*m, "material", "mass_kg", mat.totalMass_kg, 1e-9, 1e6);
            mat.structuralStiffness_N =
                number(*m, "material", "structural_stiffness_N", mat.structuralStiffness_N, 0, 1e9);
            mat.structuralDamping_Ns =
                number(*m, "material", "structural_damping_Ns", mat.structuralDamping_Ns, 0, 1e9);
            mat.positioningStiffness_N_per_m3 =
                number(*m, "material", "positioning_stiffness_N_per_m3", mat.positioningStiffness_N_per_m3, 0, 1e15);
            mat.positioningDamping_Ns_per_m3 =
                number(*m, "material", "positioning_damping_Ns_per_m3", mat.positioningDamping_Ns_per_m3, 0, 1e15);
            if (m->contains("toughness_J_per_m2"))
                s.toughness_J_per_m2 = number(*m, "material", "toughness_J_per_m2", 0, 1e-3, 1e7);
            s.bulkModulus_Pa = number(*m, "material", "bulk_modulus_Pa", s.bulkModulus_Pa, 0, 1e9);
            s.strainLimit = number(*m, "material", "strain_limit", s.strainLimit, 0, 10);
            s.materialGiven = true;
        }
        if (const toml::node* tools = root.get("tools")) {
            const toml::array* list = tools->as_array();
            if (!list) throw SceneError{lineOf(*tools), "tools: expected a list of [[tools]] tables"};
            s.tools.clear();
            for (std::size_t i = 0; i < list->size(); ++i) {
                const std::string path = "tools[" + std::to_string(i) + "]";
                const toml::table* t = (*list)[i].as_table();
                if (!t) throw SceneError{lineOf((*list)[i]), path + ": expected a table"};
                allowOnly(*t, path, {"name", "file", "threshold_N", "tip_radius_m"});
                SceneTool tool;
                tool.name = text(*t, path, "name", "");
                if (tool.name.empty()) throw SceneError{lineOf(*t), path + ".name: every tool needs a name"};
                tool.file = resolve(text(*t, path, "file", ""), directory);
                const double fallback = tool.name == "scalpel" ? mesh::procedural::kScalpelThreshold_N
                                                               : mesh::procedural::kProbeThreshold_N;
                tool.threshold_N = number(*t, path, "threshold_N", fallback, 0, 1e12);
                const double tip = tool.name == "scalpel" ? mesh::procedural::kScalpelTipRadius_m
                                   : tool.name == "probe" ? mesh::procedural::kProbeTipRadius_m
                                                          : mesh::procedural::tipRadiusForThreshold_m(tool.threshold_N);
                tool.tipRadius_m = number(*t, path, "tip_radius_m", tip, 0, 0.05);
                s.tools.push_back(tool);
            }
        }
        if (const toml::table* d = subTable(root, "device")) {
            allowOnly(
                *d, "device",
                {"backend", "trajectory", "stiffness_N_per_m", "damping_Ns_per_m", "max_force_N", "static_friction",
                 "dynamic_friction", "workspace_scale", "workspace_offset_m", "workspace_rotate_deg"});
            s.deviceBackend = text(*d, "device", "backend", s.deviceBackend, {"virtual", "replay"});
            s.trajectory = resolve(text(*d, "device", "trajectory", ""), directory);
            if (s.deviceBackend == "replay" && s.trajectory.empty())
                throw SceneError{lineOf(*d), "device.trajectory: the replay backend needs a trajectory file"};
            s.couplingStiffness_N_per_m =
                number(*d, "device", "stiffness_N_per_m", s.couplingStiffness_N_per_m, 1, 5000);
            s.couplingDamping_Ns_per_m = number(*d, "device", "damping_Ns_per_m", s.couplingDamping_Ns_per_m, 0, 100);
            s.maxForce_N = number(*d, "device", "max_force_N", s.maxForce_N, 0, 50);
            s.staticFriction = number(*d, "device", "static_friction", s.staticFriction, 0, 10);
            s.dynamicFriction = number(*d, "device", "dynamic_friction", s.dynamicFriction, 0, 10);
            if (s.dynamicFriction > s.staticFriction)
                throw SceneError{lineOf(*d), "device.dynamic_friction: must not exceed device.static_friction"};
            s.workspace.scale = number(*d, "device", "workspace_scale", 1, 1e-6, 1e6);
            s.workspace.offset_m = vector3(*d, "device", "workspace_offset_m", Vec3::Zero(), 100);
            s.workspace.rotation =
                rotationFromDegrees(vector3(*d, "device", "workspace_rotate_deg", Vec3::Zero(), 3600));
        }
        if (const toml::node* regions = root.get("regions")) {
            const toml::array* list = regions->as_array();
            if (!list) throw SceneError{lineOf(*regions), "regions: expected a list of [[regions]] tables"};
            for (std::size_t i = 0; i < list->size(); ++i) s.regions.push_back(parseRegion((*list)[i], i, directory));
        }
        if (const toml::node* devices = root.get("devices")) {
            const toml::array* list = devices->as_array();
            if (!list)
                throw SceneError{lineOf(*devices), "devices: expected a list of [[devices]] tables, one per hand"};
            if (root.get("device"))
                throw SceneError{lineOf(*devices),
                                 "devices: a scene has either one [device] table or [[devices]] tables, not both"};
            if (list->size() > static_cast<std::size_t>(haptics::kMaxHands))
                throw SceneError{lineOf(*devices), "devices: " + std::to_string(list->size()) + " devices; at most " +
                                                       std::to_string(haptics::kMaxHands) + ", one per hand"};
            for (std::size_t i = 0; i < list->size(); ++i)
                s.devices.push_back(parseDevice((*list)[i], i, s, directory));
        }
        if (const toml::table* m = subTable(root, "simulation")) {
            allowOnly(*m, "simulation",
                      {"integrator", "rate_hz", "active_region", "solver_tolerance", "solver_force_tolerance_N",
                       "solver_max_iterations", "solver_newton_iterations", "solver_threads", "physics_rate",
                       "haptic_thread_priority", "max_physics_step_ms", "solver_preconditioner"});
            const std::string rate = text(*m, "simulation", "physics_rate", "auto", {"auto", "single", "multi"});
            using PR = haptics::LoopConfig::PhysicsRate;
            s.physicsRate = rate == "single" ? PR::Single : rate == "multi" ? PR::Multi : PR::Auto;
            s.scheme = *physics::parseScheme(text(*m, "simulation", "integrator", "auto",
                                                  {"auto", "euler", "midpoint", "rk4", "symplectic", "implicit"}));
            s.solver.tolerance = number(*m, "simulation", "solver_tolerance", s.solver.tolerance, 1e-14, 1);
            s.solver.forceTolerance_N =
                number(*m, "simulation", "solver_force_tolerance_N", s.solver.forceTolerance_N, 0, 1);
            s.solver.maxIterations = static_cast<int>(wholeNumber(
                *m, "simulation", "solver_max_iterations", s.solver.maxIterations, 1, physics::kMaxSolverIterations));
            s.solver.maxNewtonIterations = static_cast<int>(
                wholeNumber(*m, "simulation", "solver_newton_iterations", s.solver.maxNewtonIterations, 1, 100));
            s.solver.preconditioner =
                *physics::parsePreconditioner(text(*m, "simulation", "solver_preconditioner",
                                                   std::string(physics::preconditionerName(s.solver.preconditioner)),
                                                   {"auto", "block-jacobi", "multilevel"}));
            s.solver.threads = static_cast<unsigned>(
                wholeNumber(*m, "simulation", "solver_threads", s.solver.threads, 0, physics::kMaxSolverThreads));
            s.rate_hz = number(*m, "simulation", "rate_hz", s.rate_hz, 100, 10'000);
            s.activeRegion = boolean(*m, "simulation", "active_region", s.activeRegion);
            s.hapticThreadPriority = static_cast<int>(
                wholeNumber(*m, "simulation", "haptic_thread_priority", s.hapticThreadPriority, 0, 99));
            s.maxPhysicsStep_s =
                number(*m, "simulation", "max_physics_step_ms", 1e3 * s.maxPhysicsStep_s, 1, 1000) / 1e3;
        }
        if (const toml::table* e = subTable(root, "exercise")) s.exercise = parseExercise(*e, s);
        if (const toml::table* r = subTable(root, "rendering")) {
            allowOnly(*r, "rendering", {"stereo", "wireframe"});
            s.stereo = text(*r, "rendering", "stereo", s.stereo, {"off", "quad", "anaglyph", "side-by-side"});
            s.wireframe = boolean(*r, "rendering", "wireframe", s.wireframe);
        }
        return s;
    } catch (const SceneError& e) {
        return unexpected(e.line < 0 ? Error{kOverlayName, -e.line, e.message} : Error{file, e.line, e.message});
    }
}

Result<std::string, std::string> settingLine(std::string_view assignment) {
    const std::size_t equals = assignment.find('=');
    const std::string key(assignment.substr(0, equals));
    const bool word = !key.empty() && key.front() != '.' && key.back() != '.' && key.find("..") == std::string::npos &&
                      std::all_of(key.begin(), key.end(), [](char c) {
                          return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.';
                      });
    if (equals == std::string_view::npos || !word)
        return unexpected("'" + std::string(assignment) +
                          "': expected KEY=VALUE with a scene key such as material.mass_kg=1.5");
    const std::string value(assignment.substr(equals + 1));
    // A TOML value (a number, true or false, "text", [a list]) as it is; anything else is text.
    try {
        const toml::table probe = toml::parse("v = " + value);
        if (probe.contains("v")) return key + " = " + value + "\n";
    } catch (const toml::parse_error&) {}
    std::string quoted = "\"";
    for (const char c : value) {
        if (c == '"' || c == '\\') quoted += '\\';
        quoted += c;
    }
    return key + " = " + quoted + "\"\n";
}

Result<SceneFile, Error> readScene(const std::filesystem::path& file, std::string_view overlay) {
    const auto contents = readTextFile(file, std::size_t{16} << 20);
    if (!contents) return unexpected(contents.error());
    return parseScene(*contents, file, file.parent_path(), overlay);
}

void centerAndFit(std::span<Vec3> positions, bool center, std::optional<double> fitSize_m) {
    if ((!center && !fitSize_m) || positions.empty()) return;
    const geometry::Aabb box = geometry::boundsOf(positions);
    const Vec3 from = box.center(), to = center ? Vec3::Zero() : from;
    const double extent = box.extent().maxCoeff();
    const double factor = fitSize_m && extent > 0 ? *fitSize_m / extent : 1.0;
    for (Vec3& p : positions) p = to + factor * (p - from);
}

void applyPlacement(const SceneFile& scene, std::span<Vec3> positions) {
    for (Vec3& p : positions) p *= scene.scale;
    centerAndFit(positions, scene.center, scene.fitSize_m);
    const Eigen::Quaterniond r = rotationFromDegrees(scene.rotate_deg);
    for (Vec3& p : positions) p = r * p + scene.translate_m;
}

}  // namespace hapticut::scene
