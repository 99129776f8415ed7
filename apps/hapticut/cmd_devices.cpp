// `hapticut devices`: every device backend, whether it works on this machine, and why not.
#include <CLI/CLI.hpp>

#include <iostream>

#include "commands.h"
#include "hapticut/haptics/openhaptics_device.h"
#include "terminal.h"

namespace hapticut::app {

namespace {

struct DevicesOptions {
    bool json = false;
    std::string hdLibrary;
};

struct Backend {
    std::string name;
    bool available = false;
    std::string detail;
};

int devices(const DevicesOptions& o) {
    std::vector<Backend> backends;
    backends.push_back({"virtual", true, "set by a program: the mouse in the viewer (hapticut view), or a script"});
    backends.push_back({"replay", true, "a recorded device path (CSV t,x,y,z,button): run --trajectory FILE, view --trajectory FILE"});
    haptics::OpenHapticsOptions hd;
    if (!o.hdLibrary.empty()) hd.libraryNames = {o.hdLibrary};
    std::string error;
    if (const auto path = haptics::OpenHapticsDevice::probeLibrary(hd, error))
        backends.push_back({"openhaptics", true, "Phantom / Touch through " + *path});
    else
        backends.push_back({"openhaptics", false, error});
    backends.push_back({"sdl", false, "not in this build yet: joysticks and gamepads through SDL2 are planned"});

    if (o.json) {
        nlohmann::ordered_json j = nlohmann::ordered_json::array();
        for (const Backend& b : backends) j.push_back({{"backend", b.name}, {"available", b.available}, {"detail", b.detail}});
        std::cout << j.dump(2) << "\n";
        return 0;
    }
    for (const Backend& b : backends) {
        std::string detail = b.detail;
        // Indent the continuation lines of multi-line reasons under the detail column.
        for (std::size_t at = detail.find('\n'); at != std::string::npos; at = detail.find('\n', at + 1)) detail.insert(at + 1, 18, ' ');
        std::printf("%-12s %-4s %s\n", b.name.c_str(), b.available ? "yes" : "no", detail.c_str());
    }
    return 0;
}

}  // namespace

Command addDevicesCommand(CLI::App& app) {
    auto o = std::make_shared<DevicesOptions>();
    CLI::App* cmd = app.add_subcommand("devices", "List the haptic device backends, whether each works here, and why not");
    cmd->add_flag("--json", o->json, "Print JSON: backend, available, detail");
    cmd->add_option("--hd-library", o->hdLibrary, "The OpenHaptics HD library to try (default: $HAPTICUT_HD_LIBRARY, else libHD.so and its versions)");
    return [o] { return devices(*o); };
}

}  // namespace hapticut::app
