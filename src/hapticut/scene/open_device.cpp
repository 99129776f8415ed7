// Opening devices by name.
#include "hapticut/scene/open_device.h"

#include <cstdio>

#include "hapticut/haptics/openhaptics_device.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/haptics/workspace_fit.h"

namespace hapticut::scene {

namespace {

/// Fits the device's reach to the model, or leaves its own mapping, and says which.
std::string mapWorkspace(haptics::Device& device, const DeviceSetup& setup) {
    const auto box = device.workspaceBox();
    if (setup.fitWorkspace && box && !setup.modelBox.empty()) {
        const haptics::WorkspaceTransform w =
            haptics::fitWorkspace(*box, setup.modelBox, setup.fitMargin, setup.sceneWorkspace.rotation);
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

Result<OpenedDevice, Error> openDevice(const haptics::DeviceName& spec, const DeviceSetup& setup) {
    auto fail = [](std::string message) { return unexpected(Error{{}, 0, std::move(message)}); };
    OpenedDevice opened;
    switch (spec.kind) {
        case haptics::DeviceKind::Virtual:
            opened.device = std::make_unique<haptics::VirtualDevice>(setup.maxForce_N);
            opened.description = "virtual";
            return opened;
        case haptics::DeviceKind::Replay: {
            auto trajectory = haptics::readTrajectory(spec.argument);
            if (!trajectory) return unexpected(trajectory.error());
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
            auto result = haptics::OpenHapticsDevice::open(hd);
            if (!result) return unexpected(result.error());
            auto device = std::move(*result);
            const std::string mapping = mapWorkspace(*device, setup);
            opened.description = device->model() + " (serial " + device->serial() + ") through " +
                                 device->libraryPath() + ", " + mapping;
            opened.device = std::move(device);
            return opened;
        }
        case haptics::DeviceKind::Sdl: {
#ifdef HAPTICUT_HAVE_SDL
            haptics::SdlOptions options;
            options.index = spec.argument.empty() ? 0 : std::stoi(spec.argument);  // parseDeviceName checked it
            options.control = setup.sdlControl;
            options.maxForce_N = setup.maxForce_N;
            if (!setup.modelBox.empty()) options.workspace.offset_m = setup.modelBox.center();
            auto result = haptics::SdlDevice::open(options);
            if (!result) return unexpected(result.error());
            auto device = std::move(*result);
            const std::string mapping = mapWorkspace(*device, setup);
            opened.description = "'" + device->info().name + "' (joystick " + std::to_string(options.index) + ", " +
                                 (options.control == haptics::SdlControl::Rate ? "rate" : "position") +
                                 " control, feedback: " + std::string(device->feedback()) + "), " + mapping;
            opened.device = std::move(device);
            return opened;
#else
            return fail(
                "this build has no SDL backend: install libsdl2-dev (scripts/install-deps does) and build again");
#endif
        }
    }
    return fail("unknown device kind");
}

Result<OpenedDevice, Error> openDeviceFor(const Scene& scene, const haptics::DeviceName& spec,
                                          const DeviceOptions& options) {
    DeviceSetup setup;
    setup.modelBox = geometry::boundsOf(scene.source.mesh.positions);
    setup.fitWorkspace = options.fitWorkspace;
    setup.hdLibrary = options.hdLibrary;
    setup.sdlControl = options.sdlControl;
    setup.maxForce_N = options.maxForce_N.value_or(scene.settings.maxForce_N);
    setup.sceneWorkspace = options.workspace.value_or(scene.settings.workspace);
    setup.sceneWorkspaceGiven = !scene.file.empty();  // the built-in scene has no mapping of its own
    return openDevice(spec, setup);
}

void applyHandSettings(const SceneDevice& device, haptics::Hand& hand) {
    hand.maxForce_N = device.maxForce_N;
    hand.maxForceRate_N_per_s = device.maxForceRate_N_per_s;
    hand.couplingStiffness_N_per_m = device.couplingStiffness_N_per_m;
    hand.couplingDamping_Ns_per_m = device.couplingDamping_Ns_per_m;
}

haptics::Hand makeHand(const Scene& scene, haptics::Device& device, const ToolTip& tip, const SceneDevice* entry) {
    haptics::Hand hand;
    hand.device = &device;
    hand.cutThreshold_N = tip.threshold_N;
    hand.tipRadius_m = tip.radius_m;
    hand.maxForce_N = scene.settings.maxForce_N;
    if (entry) applyHandSettings(*entry, hand);
    return hand;
}

DeviceOptions deviceOptionsFor(const SceneDevice& device, bool fit_workspace, const std::string& hd_library) {
    DeviceOptions options;
    options.fitWorkspace = fit_workspace && device.fitWorkspace;
    options.hdLibrary = hd_library;
    options.sdlControl = device.sdlControl == "rate" ? haptics::SdlControl::Rate : haptics::SdlControl::Position;
    options.workspace = device.workspace;
    options.maxForce_N = device.maxForce_N;
    return options;
}

}  // namespace hapticut::scene
