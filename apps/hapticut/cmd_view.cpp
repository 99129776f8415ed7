// `hapticut view`: the interactive viewer on a scene or a model.
#include <CLI/CLI.hpp>

#include <iostream>
#include <tuple>

#include "commands.h"
#include "hapticut/common/output_path.h"
#include "hapticut/haptics/device_name.h"
#include "terminal.h"
#include "unit_options.h"
#include "viewer/viewer.h"

namespace hapticut::app {

namespace {

struct ViewCommandOptions {
    viewer::ViewerOptions viewer;
    std::string model, stereo = "off", size = "1280x1024";
    UnitOptions units;
    int triangles = 1619;
};

int view(ViewCommandOptions& o) {
    const auto stereo = render::parseStereoMode(o.stereo);
    if (!stereo) {
        std::cerr << "hapticut view: unknown --stereo '" << o.stereo
                  << "': expected off, quad, anaglyph or side-by-side\n";
        return 2;
    }
    o.viewer.stereo = *stereo;
    const auto size = parseSize(o.size, 64, 16384);
    if (!size) {
        std::cerr << "hapticut view: --size takes WIDTHxHEIGHT, each 64 to 16384, found '" << o.size << "'\n";
        return 2;
    }
    std::tie(o.viewer.width, o.viewer.height) = *size;
    if (o.viewer.devices.size() > 2) {
        std::cerr << "hapticut view: " << o.viewer.devices.size() << " devices: at most two, one per hand\n";
        return 2;
    }
    for (const std::string& device : o.viewer.devices)
        if (const auto spec = haptics::parseDeviceName(device); !spec) {
            std::cerr << "hapticut view: " << spec.error().toString() << "\n";
            return 2;
        }
    o.viewer.hands = std::max(o.viewer.hands, static_cast<int>(o.viewer.devices.size()));
    if (!o.viewer.screenshot.empty() && o.viewer.frames < 0 && o.viewer.quitAfter_s < 0) {
        std::cerr << "hapticut view: --screenshot needs --frames or --quit-after: it captures the last frame\n";
        return 2;
    }
    if (const Status unwritable = checkOutputPaths({o.viewer.record, o.viewer.report})) {
        std::cerr << "hapticut view: " << unwritable->toString() << "\n";
        return 2;
    }
    if (const Status unwritable = checkOutputPath(o.viewer.screenshot, ".png")) {
        std::cerr << "hapticut view: " << unwritable->toString() << "\n";
        return 2;
    }
    return viewer::runViewer(o.viewer);
}

}  // namespace

Command addViewCommand(CLI::App& app) {
    auto o = std::make_shared<ViewCommandOptions>();
    CLI::App* cmd = app.add_subcommand(
        "view", "Open the interactive viewer: press and cut the organ with the mouse (h lists the keys)");
    cmd->add_option("--scene", o->viewer.scene.file,
                    "A scene file (TOML); default: the built-in heart with the probe and the scalpel");
    cmd->add_option("--model", o->model, "'heart' or a model file; overrides the scene's model");
    cmd->add_option("--triangles", o->triangles, "Triangle count of the procedural heart")
        ->check(CLI::Range(12, 20'000'000));
    cmd->add_option("--device", o->viewer.devices,
                    "virtual (the mouse), replay:FILE, openhaptics[:NAME] (a Phantom / Touch) or sdl[:INDEX] (a "
                    "joystick); twice for two hands")
        ->expected(1)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->capture_default_str();
    cmd->add_option("--hands", o->viewer.hands,
                    "1 or 2: a second hand with the next tool, driven by the mouse when Tab selects it")
        ->check(CLI::Range(1, 2))
        ->capture_default_str();
    cmd->add_flag(
        "--no-workspace-fit", [o](std::int64_t) { o->viewer.fitWorkspace = false; },
        "Map a hardware device 1:1 (millimetres round the organ) instead of fitting its reach to the organ");
    cmd->add_option("--tool", o->viewer.tool, "The tool in hand at the start")->capture_default_str();
    cmd->add_option("--stereo", o->stereo, "off, quad, anaglyph or side-by-side")->capture_default_str();
    cmd->add_flag("--fullscreen", o->viewer.fullscreen, "Fill the primary monitor");
    cmd->add_option("--size", o->size, "Window size WIDTHxHEIGHT")->capture_default_str();
    cmd->add_flag("--wireframe", o->viewer.wireframe, "Start in wireframe");
    cmd->add_flag("--no-panel", o->viewer.hidePanel, "Start with the panel hidden (F1 shows it)");
    cmd->add_option("--trajectory", o->viewer.trajectory, "Replay this device path instead of following the mouse");
    cmd->add_option("--frames", o->viewer.frames,
                    "Quit after this many frames, unthrottled (scripted runs, frame-rate measurements)")
        ->check(CLI::Range(0L, 100'000'000L));
    cmd->add_option("--quit-after", o->viewer.quitAfter_s, "Quit after this many seconds (scripted runs)")
        ->check(CLI::Range(0.0, 1e7));
    addUnitOptions(cmd, o->units);
    cmd->add_option("--screenshot", o->viewer.screenshot,
                    "With --frames or --quit-after: write the last frame (panel and all) as a PNG");
    cmd->add_option("--report", o->viewer.report, "Write a JSON report: frames, frame rate, haptic rate, renderer");
    cmd->add_option("--record", o->viewer.record,
                    "Record the device path at the haptic loop's rate, with the force, as a trajectory (CSV)");
    cmd->callback([o, cmd] {
        if (cmd->count("--model")) o->viewer.scene.overrides.model = o->model;
        if (cmd->count("--triangles")) o->viewer.scene.overrides.triangles = o->triangles;
        o->units.applyTo(o->viewer.scene.overrides);
        o->viewer.devicesGiven = cmd->count("--device") > 0;
        o->viewer.sizeGiven = cmd->count("--size") > 0;
    });
    return [o] { return view(*o); };
}

}  // namespace hapticut::app
