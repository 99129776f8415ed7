// `hapticut devices`: every device backend, whether it works on this machine, and why not.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <iostream>
#include <thread>

#include "commands.h"
#include "hapticut/haptics/openhaptics_device.h"
#include "hapticut/scene/open_device.h"
#include "terminal.h"

namespace hapticut::app {

namespace {

struct DevicesOptions {
    bool json = false;
    std::string hdLibrary;
    std::string selfTest;     // a device name: check it end to end
    bool forcePulse = false;  // the user's consent to a gentle push during the self-test
    double seconds = 1.0;
};

struct Check {
    std::string name;
    bool ok = false;
    std::string detail;
};

/// Drives the device for `seconds` at 1 kHz, from its own servo loop when it has one: reads every
/// sample, and (with consent) plays a gentle 0.5 N push up, faded in and out over the middle half.
struct StreamResult {
    long samples = 0, nonFinite = 0;
    geometry::Aabb reach;
    double maxForceSent_N = 0;
    double rate_hz = 0;
};

StreamResult streamDevice(haptics::Device& device, double seconds, bool pulse) {
    StreamResult r;
    using Clock = std::chrono::steady_clock;
    const auto begin = Clock::now();
    auto tick = [&]() {
        const double t = std::chrono::duration<double>(Clock::now() - begin).count();
        if (t >= seconds) {
            device.commandForce(Vec3::Zero());
            return false;
        }
        const haptics::DeviceSample s = device.read(t);
        ++r.samples;
        if (!s.position_m.allFinite())
            ++r.nonFinite;
        else
            r.reach.grow(s.position_m);
        const double x = (t - 0.25 * seconds) / (0.5 * seconds);  // 0..1 over the middle half
        const double push = pulse && x > 0 && x < 1 ? 0.5 * std::sin(M_PI * x) : 0.0;
        device.commandForce(Vec3(0, push, 0));
        r.maxForceSent_N = std::max(r.maxForceSent_N, push);
        return true;
    };
    if (haptics::ServoClock* servo = device.servoClock()) {
        if (!servo->startServo(tick)) {
            std::this_thread::sleep_for(std::chrono::duration<double>(seconds + 0.05));
            servo->stopServo();
        }
    } else {
        auto next = Clock::now();
        while (tick()) {
            next += std::chrono::milliseconds(1);
            std::this_thread::sleep_until(next);
        }
    }
    device.commandForce(Vec3::Zero());
    r.rate_hz = static_cast<double>(r.samples) / seconds;
    return r;
}

int selfTest(const DevicesOptions& o) {
    std::vector<Check> checks;
    auto finish = [&] {
        bool ok = true;
        for (const Check& c : checks) ok = ok && c.ok;
        if (o.json) {
            nlohmann::ordered_json j;
            j["device"] = o.selfTest;
            j["ok"] = ok;
            j["checks"] = nlohmann::ordered_json::array();
            for (const Check& c : checks)
                j["checks"].push_back({{"check", c.name}, {"ok", c.ok}, {"detail", c.detail}});
            std::cout << j.dump(2) << "\n";
        } else {
            for (const Check& c : checks)
                std::printf("%-10s %-4s %s\n", c.name.c_str(), c.ok ? "ok" : "FAIL", c.detail.c_str());
            std::printf("%s\n",
                        ok ? "the device works end to end" : "the device does not work: see the first FAIL above");
        }
        return ok ? 0 : 1;
    };
    const auto spec = haptics::parseDeviceName(o.selfTest);
    if (!spec) {
        std::cerr << "hapticut devices: " << spec.error().toString() << "\n";
        return 2;
    }
    scene::DeviceSetup setup;
    setup.hdLibrary = o.hdLibrary;
    setup.fitWorkspace = false;  // device units as the device reports them, scaled to metres
    auto opened = scene::openDevice(*spec, setup);
    checks.push_back({"open", opened.has_value(), opened ? opened->description : opened.error().toString()});
    if (!opened) return finish();
    haptics::Device& device = *opened->device;
    // Opening an OpenHaptics device checks its calibration and refuses one that needs the user.
    if (spec->kind == haptics::DeviceKind::OpenHaptics) checks.push_back({"calibrate", true, "calibration is current"});
    const StreamResult r = streamDevice(device, o.seconds, o.forcePulse);
    char text[200];
    std::snprintf(text, sizeof text, "%ld samples in %.2f s (%.0f Hz), %ld non-finite", r.samples, o.seconds, r.rate_hz,
                  r.nonFinite);
    checks.push_back({"positions", r.samples > 0 && r.nonFinite == 0, text});
    if (!r.reach.empty()) {
        std::snprintf(text, sizeof text,
                      "moved over %.1f x %.1f x %.1f mm (move the device during the test to see it change)",
                      r.reach.extent().x() * 1e3, r.reach.extent().y() * 1e3, r.reach.extent().z() * 1e3);
        checks.push_back({"range", true, text});
    }
    if (o.forcePulse) {
        bool faulted = false;
        std::string why;
        if (const auto* hd = dynamic_cast<const haptics::OpenHapticsDevice*>(&device)) {
            faulted = hd->faulted();
            why = hd->faultMessage();
        }
        std::snprintf(text, sizeof text, "pushed up to %.2f N for %.2f s, then zero", r.maxForceSent_N,
                      0.5 * o.seconds);
        checks.push_back({"force", !faulted && r.maxForceSent_N > 0,
                          faulted ? "the device faulted during the push: " + why : std::string(text)});
    } else {
        checks.push_back(
            {"force", true, "not tried: add --force-pulse to let the device push the stylus gently (hold it loosely)"});
    }
    return finish();
}

struct Backend {
    std::string name;
    bool available = false;
    std::string detail;
};

int devices(const DevicesOptions& o) {
    if (!o.selfTest.empty()) return selfTest(o);
    std::vector<Backend> backends;
    backends.push_back({"virtual", true, "set by a program: the mouse in the viewer (hapticut view), or a script"});
    backends.push_back(
        {"replay", true, "a recorded device path (CSV t,x,y,z,button): run --trajectory FILE, view --trajectory FILE"});
    haptics::OpenHapticsOptions hd;
    if (!o.hdLibrary.empty()) hd.libraryNames = {o.hdLibrary};
    if (const auto path = haptics::OpenHapticsDevice::probeLibrary(hd))
        backends.push_back({"openhaptics", true, "Phantom / Touch through " + *path});
    else
        backends.push_back({"openhaptics", false, path.error().message});
    nlohmann::ordered_json joysticks = nlohmann::ordered_json::array();
#ifdef HAPTICUT_HAVE_SDL
    const auto listed = haptics::SdlDevice::list();
    const std::vector<haptics::SdlJoystickInfo> found = listed ? *listed : std::vector<haptics::SdlJoystickInfo>{};
    if (!listed) {
        backends.push_back({"sdl", false, listed.error().message});
    } else if (found.empty()) {
        backends.push_back({"sdl", false,
                            "SDL sees no joystick or gamepad (plugged in? may this user read /dev/input/event*? On "
                            "Debian: the 'input' group)"});
    } else {
        std::string detail;
        for (const haptics::SdlJoystickInfo& js : found) {
            detail += (detail.empty() ? "" : "\n") + std::string("sdl:") + std::to_string(js.index) + " '" + js.name +
                      "', " + std::to_string(js.axes) + " axes, feedback: " +
                      (js.constantForce ? "constant force"
                       : js.rumble      ? "rumble"
                                        : "none");
            joysticks.push_back({{"index", js.index},
                                 {"name", js.name},
                                 {"axes", js.axes},
                                 {"buttons", js.buttons},
                                 {"constant_force", js.constantForce},
                                 {"rumble", js.rumble}});
        }
        backends.push_back({"sdl", true, detail});
    }
#else
    backends.push_back(
        {"sdl", false,
         "this build has no SDL backend: install libsdl2-dev (scripts/install-deps does) and build again"});
#endif

    if (o.json) {
        nlohmann::ordered_json j = nlohmann::ordered_json::array();
        for (const Backend& b : backends) {
            j.push_back({{"backend", b.name}, {"available", b.available}, {"detail", b.detail}});
            if (b.name == "sdl") j.back()["joysticks"] = joysticks;
        }
        std::cout << j.dump(2) << "\n";
        return 0;
    }
    for (const Backend& b : backends) {
        std::string detail = b.detail;
        // Indent the continuation lines of multi-line reasons under the detail column.
        for (std::size_t at = detail.find('\n'); at != std::string::npos; at = detail.find('\n', at + 1))
            detail.insert(at + 1, 18, ' ');
        std::printf("%-12s %-4s %s\n", b.name.c_str(), b.available ? "yes" : "no", detail.c_str());
    }
    return 0;
}

}  // namespace

Command addDevicesCommand(CLI::App& app) {
    auto o = std::make_shared<DevicesOptions>();
    CLI::App* cmd =
        app.add_subcommand("devices", "List the haptic device backends, whether each works here, and why not");
    cmd->add_flag("--json", o->json, "Print JSON: backend, available, detail");
    cmd->add_option(
        "--hd-library", o->hdLibrary,
        "The OpenHaptics HD library to try (default: $HAPTICUT_HD_LIBRARY, else libHD.so and its versions)");
    cmd->add_option(
        "--self-test", o->selfTest,
        "Check one device end to end: openhaptics[:NAME], sdl[:INDEX] or replay:FILE; exit 0 when it works");
    cmd->add_flag("--force-pulse", o->forcePulse,
                  "With --self-test: let the device push gently (0.5 N, half a second); hold the stylus loosely");
    cmd->add_option("--seconds", o->seconds, "With --self-test: how long to read the device")
        ->capture_default_str()
        ->check(CLI::Range(0.1, 60.0));
    return [o] { return devices(*o); };
}

}  // namespace hapticut::app
