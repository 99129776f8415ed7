// Opens the device a name (`--device`, a scene's [[devices]]) gives, mapped onto the model: what `run`,
// `view` and `devices --self-test` share. Device errors come back in words, never as a crash.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/geometry/aabb.h"
#include "hapticut/haptics/device.h"
#include "hapticut/haptics/device_name.h"
#include "hapticut/haptics/sdl_device.h"
#include "hapticut/scene/scene.h"

namespace hapticut::scene {

struct DeviceSetup {
    geometry::Aabb modelBox;   // the automatic fit maps the device's reach onto this, grown by fitMargin
    bool fitWorkspace = true;  // else: millimetres 1:1 round the model's centre (openhaptics), +-5 cm (sdl)
    double fitMargin = 0.2;
    haptics::WorkspaceTransform sceneWorkspace;  // a scene's own [device] mapping; used when not fitting
    bool sceneWorkspaceGiven = false;
    double maxForce_N = haptics::kDefaultMaxForce_N;
    std::string hdLibrary;  // openhaptics: the HD library to try first
    haptics::SdlControl sdlControl = haptics::SdlControl::Position;
};

struct OpenedDevice {
    std::unique_ptr<haptics::Device> device;
    std::string description;  // "Touch (serial 12345) through /opt/.../libHD.so, workspace fitted: 1.62 x"
};

/// The device, opened and mapped, or an error saying what is missing and what to do.
Result<OpenedDevice, Error> openDevice(const haptics::DeviceName& spec, const DeviceSetup& setup);

/// What a command line changes in how a scene's devices open.
struct DeviceOptions {
    bool fitWorkspace =
        true;               // fit each device's reach to the organ; else the scene file's mapping, or the device's own
    std::string hdLibrary;  // openhaptics: the HD library to try first
    haptics::SdlControl sdlControl = haptics::SdlControl::Position;
    /// A [[devices]] entry's own mapping and force limit, instead of the [device] table's.
    std::optional<haptics::WorkspaceTransform> workspace;
    std::optional<double> maxForce_N;
};

/// The options a scene's [[devices]] entry sets, with `fit_workspace` false when the command line says so.
DeviceOptions deviceOptionsFor(const SceneDevice& device, bool fit_workspace, const std::string& hd_library);

/// Gives a hand its [[devices]] entry's own force limits and coupling.
void applyHandSettings(const SceneDevice& device, haptics::Hand& hand);

/// A hand holding `device` with the tool whose tip is `tip`, under the scene's force limit or, when the
/// hand is a [[devices]] entry (`entry`, else null), under that entry's own limits and coupling.
haptics::Hand makeHand(const Scene& scene, haptics::Device& device, const ToolTip& tip, const SceneDevice* entry);

/// Opens a device for a hand on the scene's organ: mapped onto it and limited to the scene's maximum force.
Result<OpenedDevice, Error> openDeviceFor(const Scene& scene, const haptics::DeviceName& spec,
                                          const DeviceOptions& options);

}  // namespace hapticut::scene
