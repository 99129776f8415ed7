// Opening devices by name.
#include "device_setup.h"

#include <cstdio>

#include "hapticut/haptics/openhaptics_device.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/haptics/workspace_fit.h"

namespace hapticut::app {

namespace {

/// Fits the device's reach to the model, or leaves its own mapping, and says which.
std::string mapWorkspace(haptics::Device& device, const DeviceSetup& setup) {
    const auto box = device.workspaceBox();
    if (setup.fitWorkspace && box && !setup.modelBox.empty()) {
        const haptics::WorkspaceTransform w = haptics::fitWorkspace(*box, setup.modelBox, setup.fitMargin, setup.sceneWorkspace.rotation);
        device.setWorkspace(w);
        char text[96];
        std::snprintf(text, sizeof text, "workspace fitted to the model (%.3g m per device unit)", w.scale);
        return text;
    }
    if (setup.sceneWorkspaceGiven) {
        device.setWorkspace(setup.sceneWorkspace);
        return "the scene's workspace mapping";
    }
    return "the device's default mapping";
}

}  // namespace

bool sdlBackendBuilt() {
#ifdef HAPTICUT_HAVE_SDL
    return true;
#else
    return false;
#endif
}

std::optional<OpenedDevice> openDevice(const haptics::DeviceSpec& spec, const DeviceSetup& setup, std::string& error) {
    OpenedDevice opened;
    switch (spec.kind) {
        case haptics::DeviceKind::Virtual:
            opened.device = std::make_unique<haptics::VirtualDevice>(setup.maxForce_N);
            opened.description = "virtual";
            return opened;
        case haptics::DeviceKind::Replay: {
            auto trajectory = haptics::readTrajectory(spec.argument);
            if (!trajectory) {
                error = trajectory.error().toString();
                return std::nullopt;
            }
            opened.description = "replay of " + spec.argument;
            opened.device = std::make_unique<haptics::ReplayDevice>(std::move(*trajectory), setup.maxForce_N);
            return opened;
        }
        case haptics::DeviceKind::OpenHaptics: {
            haptics::OpenHapticsOptions hd;
            hd.deviceName = spec.argument;
            if (!setup.hdLibrary.empty()) hd.libraryNames = {setup.hdLibrary};
            // Without a fit: device millimetres round the organ's centre, where a Touch holds a heart at 1:1.
            if (!setup.modelBox.empty()) hd.workspace.offset_m = setup.modelBox.center();
            auto device = haptics::OpenHapticsDevice::open(hd, error);
            if (!device) return std::nullopt;
            const std::string mapping = mapWorkspace(*device, setup);
            opened.description = device->model() + " (serial " + device->serial() + ") through " + device->libraryPath() + ", " + mapping;
            opened.device = std::move(device);
            return opened;
        }
        case haptics::DeviceKind::Sdl: {
#ifdef HAPTICUT_HAVE_SDL
            haptics::SdlOptions options;
            options.index = spec.argument.empty() ? 0 : std::stoi(spec.argument);  // parseDeviceSpec checked it
            options.control = setup.sdlControl;
            options.maxForce_N = setup.maxForce_N;
            if (!setup.modelBox.empty()) options.workspace.offset_m = setup.modelBox.center();
            auto device = haptics::SdlDevice::open(options, error);
            if (!device) return std::nullopt;
            const std::string mapping = mapWorkspace(*device, setup);
            opened.description = "'" + device->info().name + "' (joystick " + std::to_string(options.index) + ", " +
                                 (options.control == haptics::SdlControl::Rate ? "rate" : "position") + " control, feedback: " +
                                 std::string(device->feedback()) + "), " + mapping;
            opened.device = std::move(device);
            return opened;
#else
            error = "this build has no SDL backend: install libsdl2-dev (scripts/install-deps does) and build again";
            return std::nullopt;
#endif
        }
    }
    error = "unknown device kind";
    return std::nullopt;
}

}  // namespace hapticut::app
