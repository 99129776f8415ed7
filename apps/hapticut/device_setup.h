// Opens the device a --device names, mapped onto the model: what `run`, `view` and `devices
// --self-test` share. Device errors come back in words, never as a crash.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "hapticut/geometry/aabb.h"
#include "hapticut/haptics/device.h"
#include "hapticut/haptics/device_spec.h"
#include "hapticut/haptics/sdl_device.h"

namespace hapticut::app {

struct DeviceSetup {
    geometry::Aabb modelBox;        // the automatic fit maps the device's reach onto this, grown by fitMargin
    bool fitWorkspace = true;       // else: millimetres 1:1 round the model's centre (openhaptics), +-5 cm (sdl)
    double fitMargin = 0.2;
    haptics::WorkspaceTransform sceneWorkspace;  // a scene's own [device] mapping; used when not fitting
    bool sceneWorkspaceGiven = false;
    double maxForce_N = haptics::kDefaultMaxForce_N;
    std::string hdLibrary;          // openhaptics: the HD library to try first
    haptics::SdlControl sdlControl = haptics::SdlControl::Position;
};

struct OpenedDevice {
    std::unique_ptr<haptics::Device> device;
    std::string description;  // "Touch (serial 12345) through /opt/.../libHD.so, workspace fitted: 1.62 x"
};

/// The device, opened and mapped; nothing with `error` saying what is missing and what to do.
std::optional<OpenedDevice> openDevice(const haptics::DeviceSpec& spec, const DeviceSetup& setup, std::string& error);

/// Whether this build has the SDL backend (Debian's libsdl2 at build time).
bool sdlBackendBuilt();

}  // namespace hapticut::app
