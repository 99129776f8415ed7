// `hapticut screenshot`: runs a scene headless up to a time, renders it offscreen and writes a PNG.
#include <CLI/CLI.hpp>

#include <cmath>
#include <iostream>

#include "commands.h"
#include "hapticut/common/output_path.h"
#include "hapticut/cutting/cut_model.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/scene/haptic_run.h"
#include "hapticut/scene/scene.h"
#include "render/gl_context.h"
#include "render/offscreen.h"
#include "render/renderer.h"
#include "terminal.h"
#include "unit_options.h"

namespace hapticut::app {

namespace {

struct ScreenshotOptions {
    scene::SceneRequest scene;
    std::string model, size = "1280x1024", out, trajectory, tool, stereo = "off";
    int triangles = 1619;
    UnitOptions units;
    double at_s = -1;
    bool wireframe = false, noBump = false, noWalls = false;
    double yaw_deg = 0, pitch_deg = 12, zoom = 1;
};

int screenshot(ScreenshotOptions& o) {
    const auto size = parseSize(o.size, 16, 16384);
    if (!size) {
        std::cerr << "hapticut screenshot: --size takes WIDTHxHEIGHT, each 16 to 16384, found '" << o.size << "'\n";
        return 2;
    }
    const auto [width, height] = *size;
    const auto stereo = render::parseStereoMode(o.stereo);
    if (!stereo) {
        std::cerr << "hapticut screenshot: unknown --stereo '" << o.stereo
                  << "': expected off, quad, anaglyph or side-by-side\n";
        return 2;
    }
    if (const Status unwritable = checkOutputPath(o.out, ".png")) {
        std::cerr << "hapticut screenshot: " << unwritable->toString() << "\n";
        return 2;
    }
    if (o.at_s >= 0 && o.trajectory.empty()) {
        std::cerr << "hapticut screenshot: --at needs --trajectory: it is a time along the device's path\n";
        return 2;
    }
    auto loaded = app::loadScene(o.scene);
    if (!loaded) return 1;

    std::optional<std::size_t> tool;
    if (!o.tool.empty() || !o.trajectory.empty()) {
        const std::string name = o.tool.empty() ? "probe" : o.tool;
        tool = loaded->toolIndex(name);
        if (!tool) {
            std::cerr << "hapticut screenshot: unknown tool '" << name << "': the scene has";
            for (const scene::Tool& t : loaded->tools) std::cerr << " " << t.name;
            std::cerr << "\n";
            return 2;
        }
    }

    // The organ as the run leaves it: at rest, or after the device's path up to --at.
    cutting::CutModel organ = loaded->makeOrgan();
    render::SceneFrame frame;
    frame.showDevice = false;
    if (!o.trajectory.empty()) {
        const auto trajectory = haptics::readTrajectory(o.trajectory);
        if (!trajectory) {
            std::cerr << trajectory.error().toString() << "\n";
            return 1;
        }
        const double end_s = trajectory->duration_s();
        if (o.at_s > end_s + 1e-9) {
            std::cerr << "hapticut screenshot: --at " << o.at_s << " s is past the end of " << o.trajectory << " ("
                      << end_s << " s)\n";
            return 2;
        }
        scene::HapticRunConfig config;
        config.loop = loaded->loopConfig();
        config.loop.cutThreshold_N = loaded->tools[*tool].threshold_N;
        config.loop.tipRadius_m = loaded->tools[*tool].tipRadius_m;
        config.steps = std::lround((o.at_s >= 0 ? o.at_s : end_s) * config.loop.rate_hz) + 1;
        auto run = scene::runHaptic(organ, *trajectory, config);
        if (!run) {
            std::cerr << "hapticut screenshot: " << run.error().toString() << "\n";
            return 1;
        }
        const scene::HapticRunResult& r = *run;
        if (r.steps > 0) {
            const haptics::StepOutput& last = r.lastStep;
            frame.hands[0].proxy_m = last.hand().proxy_m;
            frame.hands[0].device_m = last.hand().device_m;
            frame.hands[0].force_N = last.hand().force_N;
            frame.hands[0].contact = last.hand().contact;
        }
        frame.showDevice = true;
        std::cerr << "hapticut screenshot: ran " << r.steps << " steps (" << r.simTime_s << " s) of " << o.trajectory
                  << " with the " << loaded->tools[*tool].name << (r.cut.cuts > 0 ? ", which cut the organ" : "")
                  << "\n";
    }
    frame.organPositions = organ.model().nodes.position;
    frame.faces = organ.mesh().faces;
    frame.uvs = organ.mesh().uvs;
    frame.wallFaces = organ.wallFaces();
    frame.hands[0].tool = tool ? static_cast<int>(*tool) : -1;
    frame.maxForce_N = loaded->settings.maxForce_N;

    std::string error;
    render::WindowOptions windowOptions;
    windowOptions.width = 64;
    windowOptions.height = 64;
    windowOptions.visible = false;
    auto window = render::GlWindow::open(windowOptions, error);
    if (!window) {
        std::cerr << "hapticut screenshot: " << error << "\n";
        return 1;
    }
    std::vector<mesh::SurfaceMesh> toolMeshes;
    for (const scene::Tool& t : loaded->tools) toolMeshes.push_back(t.mesh);
    auto renderer = render::Renderer::create(toolMeshes, error);
    auto target = renderer ? render::OffscreenTarget::create(width, height, 4, error) : nullptr;
    if (!target) {
        std::cerr << "hapticut screenshot: " << error << " (" << window->rendererDescription() << ")\n";
        return 1;
    }

    render::ViewSettings view;
    view.stereo = *stereo == render::StereoMode::QuadBuffer ? render::StereoMode::Anaglyph : *stereo;
    if (*stereo == render::StereoMode::QuadBuffer)
        std::cerr << "hapticut screenshot: a PNG has no quad buffer; drawing anaglyph instead\n";
    view.wireframe = o.wireframe || loaded->settings.wireframe;
    view.normalMapping = !o.noBump;
    view.woundWalls = !o.noWalls;
    view.camera.yaw_rad = o.yaw_deg * M_PI / 180;
    view.camera.pitch_rad = o.pitch_deg * M_PI / 180;
    view.frameOrgan(loaded->source.mesh.positions, o.zoom);

    renderer->setOrganRims(loaded->source.mesh.faces);
    target->bind();
    renderer->draw(frame, view, width, height);
    const render::Image image = target->read();
    if (const auto failed = render::savePng(o.out, image)) {
        std::cerr << "hapticut screenshot: " << *failed << "\n";
        return 1;
    }
    std::cout << "wrote a " << width << "x" << height << " screenshot of " << loaded->source.name << " to " << o.out
              << " (" << window->rendererDescription() << ")\n";
    return 0;
}

}  // namespace

Command addScreenshotCommand(CLI::App& app) {
    auto o = std::make_shared<ScreenshotOptions>();
    CLI::App* cmd =
        app.add_subcommand("screenshot", "Render a scene offscreen to a PNG, optionally after running a device path");
    cmd->add_option("--scene", o->scene.file,
                    "A scene file (TOML); default: the built-in heart with the probe and the scalpel");
    cmd->add_option("--model", o->model, "'heart' or a model file; overrides the scene's model");
    cmd->add_option("--triangles", o->triangles, "Triangle count of the procedural heart")
        ->check(CLI::Range(12, 20'000'000));
    cmd->add_option("--trajectory", o->trajectory,
                    "Run the haptic loop along this device path (CSV t,x,y,z,button) first");
    cmd->add_option("--at", o->at_s, "Stop the path at this time (s); default: its end")->check(CLI::Range(0.0, 1e6));
    cmd->add_option("--tool", o->tool,
                    "The scene's tool to hold (probe, scalpel, ...); default probe when a path is given");
    cmd->add_option("--stereo", o->stereo, "off, anaglyph, side-by-side (quad falls back to anaglyph)")
        ->capture_default_str();
    cmd->add_flag("--wireframe", o->wireframe, "Draw the organ's edges instead of shading it");
    cmd->add_flag("--no-bump", o->noBump, "Turn off bump (normal) mapping");
    cmd->add_flag("--no-walls", o->noWalls, "Leave opened wounds without their walls (see through the gap)");
    cmd->add_option("--yaw", o->yaw_deg, "Camera turned about the vertical, degrees (0: from the front)")
        ->capture_default_str();
    cmd->add_option("--pitch", o->pitch_deg, "Camera raised above the horizontal, degrees")
        ->capture_default_str()
        ->check(CLI::Range(-85.0, 85.0));
    cmd->add_option("--zoom", o->zoom, "Closer (>1) or further (<1) than the framing of the whole organ")
        ->capture_default_str()
        ->check(CLI::Range(0.05, 50.0));
    cmd->add_option("--size", o->size, "Image size WIDTHxHEIGHT")->capture_default_str();
    cmd->add_option("--out", o->out, "The PNG to write")->required();
    addUnitOptions(cmd, o->units);
    cmd->callback([o, cmd] {
        if (cmd->count("--model")) o->scene.overrides.model = o->model;
        if (cmd->count("--triangles")) o->scene.overrides.triangles = o->triangles;
        o->units.applyTo(o->scene.overrides);
    });
    return [o] { return screenshot(*o); };
}

}  // namespace hapticut::app
