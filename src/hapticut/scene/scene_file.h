// Scene files (TOML): an experiment described in a file rather than in code (SPEC R23).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hapticut/common/result.h"
#include "hapticut/common/text_file.h"
#include "hapticut/haptics/device.h"
#include "hapticut/haptics/device_name.h"
#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"

namespace hapticut::scene {

struct SceneTool {
    std::string name;  // "probe", "scalpel", or any name for a tool file
    std::string file;  // a tool file (thesis format); empty: the procedural tool of that name
    double threshold_N = 1e9;
    double tipRadius_m = 0;  // its tip spreads its load over this radius (haptics/contact_footprint.h); 0: a point
};

/// Tissue with a material of its own (a lump, a tumour): a [[regions]] table, in the scene's coordinates.
struct SceneRegion {
    enum class Shape { Sphere, Box, Mesh } shape = Shape::Sphere;
    Vec3 center_m = Vec3::Zero();  // sphere and box
    double radius_m = 0;           // sphere
    Vec3 size_m = Vec3::Zero();    // box: its extent along x, y and z, about center_m
    std::string mesh;              // mesh: a closed surface file in metres, resolved against the scene's folder
    double stiffnessScale = 1;     // its springs' and anchors' stiffness multiplied
    double dampingScale = 1;
    double toughnessScale = 1;  // the fracture toughness a blade meets there multiplied
    bool hidden = false;        // a lump a palpation exercise asks to find by touch
    int line = 0;               // of its [[regions]] header, for errors about it
};

/// A training exercise: the scene's [exercise] table, in the scene's coordinates (scene/assessment
/// scores a session of it).
struct SceneExercise {
    enum class Kind { Incision, Palpation } kind = Kind::Incision;
    std::string instructions;  // shown in the viewer
    double timeLimit_s = 0;    // 0: none; a session is scored on what it did within the limit
    std::string tool;          // the tool it is done with, a [[tools]] name; empty: the scalpel or the probe
    // Incision: the target line runs through these points of the rest surface, along the surface.
    std::vector<Vec3> path_m;
    std::vector<int> pathLines;  // each point's line, for errors about it
    double corridor_m = 0.003;   // half the width a cut may stray from the target
    double depth_m = 0.005;      // how deep the blade should go
    // Palpation: how close a mark must be to the surface point above a hidden region.
    double radius_m = 0.01;
    /// The most force the tissue should feel; above it the force's part of the score shrinks.
    double maxForce_N = 4;
    int line = 0;  // of the [exercise] header
};

/// One hand's device: a [[devices]] table.
struct SceneDevice {
    haptics::DeviceName device;  // as --device names it; a replay's file resolved against the scene's folder
    std::string tool;            // a [[tools]] name; empty: the command line's --tool (the probe by default)
    std::optional<double> couplingStiffness_N_per_m, couplingDamping_Ns_per_m;  // empty: [device]'s or the defaults
    double maxForce_N = haptics::kDefaultMaxForce_N;
    double maxForceRate_N_per_s = haptics::kDefaultMaxForceRate_N_per_s;
    bool fitWorkspace = true;  // workspace = "fit": the device's reach fitted to the organ; "mapped": the keys below
    haptics::WorkspaceTransform workspace;
    std::string sdlControl = "position";  // a joystick's axes as position or rate
    int line = 0;                         // where the table starts, for messages about it
};

struct SceneFile {
    // [model]
    std::string model = "heart";  // "heart" or a mesh file, resolved against the scene's folder
    int triangles = 1619;
    Vec3 translate_m = Vec3::Zero();
    Vec3 rotate_deg = Vec3::Zero();  // about x, then y, then z
    double scale = 1;
    bool center = false;              // the bounding box's centre moved to the origin (after scale)
    std::optional<double> fitSize_m;  // scaled about its centre so that its largest extent is this
    std::vector<std::string> parts;   // only these named parts of the model file; empty: all
    // [material]: resolution-independent; applied to thesis files too when given
    physics::Material material;
    bool materialGiven = false;
    /// [material] toughness_J_per_m2: the tissue's fracture toughness (cutting/fracture.h); empty: each
    /// blade's from its tool's threshold.
    std::optional<double> toughness_J_per_m2;
    /// [material] bulk_modulus_Pa: a closed organ keeps its volume by a pressure of this modulus; 0: off.
    double bulkModulus_Pa = 0;
    /// [material] strain_limit: Provot's limit on spring stretch (0.1: 10%); 0: off.
    double strainLimit = 0;
    // [[regions]]: where one holds a point, the last that holds it
    std::vector<SceneRegion> regions;
    // [[tools]]
    std::vector<SceneTool> tools;
    // [exercise]
    std::optional<SceneExercise> exercise;
    // [device]
    std::string deviceBackend = "virtual";  // virtual or replay
    std::string trajectory;                 // replay: a trajectory CSV, resolved against the scene's folder
    double couplingStiffness_N_per_m = 400, couplingDamping_Ns_per_m = 0.3, maxForce_N = haptics::kDefaultMaxForce_N;
    double staticFriction = 0, dynamicFriction = 0;
    haptics::WorkspaceTransform workspace;
    // [[devices]]: one per hand, at most two; empty when the scene has the single [device] table (or neither)
    std::vector<SceneDevice> devices;
    // [simulation]
    physics::Scheme scheme = physics::Scheme::Auto;
    physics::SolverSettings solver;
    double rate_hz = 1000;
    bool activeRegion = true;
    haptics::LoopConfig::PhysicsRate physicsRate = haptics::LoopConfig::PhysicsRate::Auto;
    int hapticThreadPriority = haptics::LoopConfig{}.hapticThreadPriority;  // SCHED_FIFO; 0: normal
    double maxPhysicsStep_s = haptics::LoopConfig{}.maxPhysicsStep_s;       // multi-rate: a step's longest
    // [rendering]
    std::string stereo = "off";  // off, quad, anaglyph, side-by-side
    bool wireframe = false;
};

/// The built-in default: the heart with the probe and the scalpel.
SceneFile defaultScene();

/// What errors in an overlay name as their file.
inline constexpr const char* kOverlayName = "<settings>";

/// Parses a scene; relative paths are resolved against `directory`. `overlay`, more TOML (a script's or a
/// sweep's settings: `material.mass_kg = 0.5`), is set over the file's keys before they are read, and
/// checked as they are. Errors name the file (or kOverlayName), the line, the key's path and what is allowed.
Result<SceneFile, Error> parseScene(std::string_view text, const std::filesystem::path& file_for_errors,
                                    const std::filesystem::path& directory, std::string_view overlay = {});
Result<SceneFile, Error> readScene(const std::filesystem::path& file, std::string_view overlay = {});

/// A command line's `--set KEY=VALUE` as an overlay's line: `material.mass_kg=1.5` keeps its number,
/// `simulation.integrator=rk4` has its text quoted; an error for a missing '=' or a key that is not
/// dotted words.
Result<std::string, std::string> settingLine(std::string_view assignment);

/// Moves, turns and scales positions by the scene's placement: scale, centre, fit, then rotation, then
/// translation.
void applyPlacement(const SceneFile& scene, std::span<Vec3> positions);

/// Moves the bounding box's centre to the origin (`center`) and scales about that centre so that the
/// largest extent is `fitSize_m` (if given): a model in body coordinates, half a metre from the origin,
/// placed where tools and trajectories expect an organ.
void centerAndFit(std::span<Vec3> positions, bool center, std::optional<double> fitSize_m);

}  // namespace hapticut::scene
