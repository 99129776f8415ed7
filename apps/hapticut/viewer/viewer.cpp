// The viewer's window loop: events, the mouse device, one rendered frame, the panel, swap.
#include "viewer/viewer.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "hapticut/common/stop_signal.h"
#include "hapticut/common/text_file.h"
#include "hapticut/common/thread_priority.h"
#include "hapticut/geometry/aabb.h"
#include "hapticut/haptics/openhaptics_device.h"
#include "hapticut/scene/open_device.h"
#include "hapticut/scene/simulation.h"
#include "provenance.h"
#include "render/gl_context.h"
#include "render/offscreen.h"
#include "render/renderer.h"
#include "render/snapshot_frame.h"
#include "viewer/exercise_mode.h"
#include "viewer/force_plot.h"
#include "viewer/mouse_device.h"
#include "viewer/overlay.h"
#include "viewer/panel.h"

namespace hapticut::viewer {

namespace {

using Clock = std::chrono::steady_clock;

/// The nice value the renderer's own threads get (the haptic loop keeps the default, 0).
constexpr int kRendererNiceness = 10;

class Viewer {
public:
    Viewer(const ViewerOptions& options, std::unique_ptr<render::GlWindow> window,
           std::unique_ptr<render::Renderer> renderer, scene::Scene scene)
        : options_(options),
          window_(std::move(window)),
          renderer_(std::move(renderer)),
          session_(std::move(scene)),
          exercise_(session_.scene(), options.record) {
        view_.stereo = options.stereo;
        view_.quadBufferAvailable = window_->hasQuadStereo();
        view_.wireframe = options.wireframe || session_.scene().settings.wireframe;
        showPanel_ = !options.hidePanel;
        // Half-right and a little above, not head-on: a press straight into the front then shows as a
        // dent with the force arrow beside it instead of a shading change and a dot.
        view_.camera.yaw_rad = 0.55;
        view_.camera.pitch_rad = 0.3;
        frameOrgan();
        if (const auto tool = session_.scene().toolIndex(options.tool)) session_.setTool(*tool);
    }

    int run();
    void frameOrgan();
    double freeViewCentre() const;
    std::vector<std::string> yieldingThreads;  // the driver's threads that yield to the haptic loop, for the report

private:
    void onKey(int key, int mods);
    void onMouseButton(int button, int action, int mods);
    void onScroll(double dy);
    void onCursor(double x, double y);
    void updateDevice(const haptics::Snapshot& snapshot);
    render::Ray cursorRay() const;
    void drawOverlay(const haptics::Snapshot& s);

    static Viewer& of(GLFWwindow* w) { return *static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

    ViewerOptions options_;
    std::unique_ptr<render::GlWindow> window_;
    std::unique_ptr<render::Renderer> renderer_;
    scene::Simulation session_;
    render::ViewSettings view_;
    MouseDriver mouse_;
    ForcePlot plot_;
    PanelState panel_;
    ExerciseMode exercise_;    // after session_, whose scene it reads
    double markUntil_s_ = -1;  // the mouse holds its second button (a mark, key m) until then (ImGui's clock)
    bool showPanel_ = true, showHelp_ = false, paused_ = false;
    double bladeTurn_deg_ = 0;  // the mouse's blade, about its handle ([ and ])
    bool bladeTurned_ = false;
    bool orbiting_ = false, panning_ = false;
    bool engagedOnce_ = false;  // the start hint shows until the mouse first takes hold
    std::string framedModel_;
    long drawnResets_ = -1;
    double cursorX_ = 0, cursorY_ = 0, lastX_ = 0, lastY_ = 0;
};

void Viewer::frameOrgan() {
    framedModel_ = session_.scene().source.name;
    const auto& positions = session_.scene().source.mesh.positions;
    int w = 0, h = 0;
    glfwGetWindowSize(window_->handle(), &w, &h);
    // In the part of the window the panel leaves free: a wide organ (a liver, 25 cm across) framed in
    // the whole window lay half under the panel.
    const double covered = freeViewCentre();
    view_.frameOrgan(positions, 1, (1 - covered) * w / std::max(h, 1));
    view_.camera.centreX_ndc = covered;
    view_.forceArrowLength_m_per_N =
        0.1 * geometry::boundsOf(positions).extent().norm() / std::max(session_.scene().settings.maxForce_N, 0.1);
}

double Viewer::freeViewCentre() const {
    // The panel covers the window's left up to its right edge, so the middle of the rest lies at the
    // covered fraction in device coordinates. Side by side, each half is a view of its own.
    int w = 0, h = 0;
    glfwGetWindowSize(window_->handle(), &w, &h);
    if (!showPanel_ || view_.stereo == render::StereoMode::SideBySide || w <= 0) return 0;
    return std::clamp(static_cast<double>(panel_.rightEdge_px) / w, 0.0, 0.5);
}

render::Ray Viewer::cursorRay() const {
    int w = 0, h = 0;
    glfwGetWindowSize(window_->handle(), &w, &h);
    double x = cursorX_, width = w;
    // Side by side: each half is a view of its own; aim from the half the cursor is in.
    if (view_.stereo == render::StereoMode::SideBySide) {
        width = w / 2.0;
        if (x > width) x -= width;
    }
    const double ndcX = 2 * x / std::max(width, 1.0) - 1, ndcY = 1 - 2 * cursorY_ / std::max(h, 1);
    return render::rayThrough(view_.camera, ndcX, ndcY, width / std::max(h, 1));
}

void Viewer::onKey(int key, int mods) {
    using render::StereoMode;
    // A key that changes the view moves the ray under a still cursor: the mouse lets go first, so the
    // tool it held jumps free instead of being dragged through the tissue; pressing again touches again.
    if (key == GLFW_KEY_S || key == GLFW_KEY_F || (key >= GLFW_KEY_4 && key <= GLFW_KEY_7)) mouse_.release();
    switch (key) {
        case GLFW_KEY_TAB:
            // The mouse lets go of this hand, which stays where it is, and takes the other.
            if (session_.handCount() == 2) {
                mouse_.release();
                session_.setActiveHand(1 - session_.activeHand());
            }
            break;
        case GLFW_KEY_LEFT_BRACKET:
        case GLFW_KEY_RIGHT_BRACKET:
            // From the first turn on, the mouse reports an orientation and the blade cuts the way its edge
            // faces; before it, the blade cuts the way the mouse moves it.
            bladeTurn_deg_ += key == GLFW_KEY_LEFT_BRACKET ? -15 : 15;
            bladeTurned_ = true;
            break;
        case GLFW_KEY_M:
            // A mark: the second button for a few steps of the loop, wherever the mouse holds the tool.
            markUntil_s_ = ImGui::GetTime() + 0.15;
            panel_.notice.say("marked", false);
            break;
        case GLFW_KEY_1: session_.setTool(0); break;
        case GLFW_KEY_2: session_.setTool(1); break;
        case GLFW_KEY_W: view_.wireframe = !view_.wireframe; break;
        case GLFW_KEY_B: view_.normalMapping = !view_.normalMapping; break;
        case GLFW_KEY_S:
            view_.stereo = view_.stereo == StereoMode::Off          ? StereoMode::Anaglyph
                           : view_.stereo == StereoMode::Anaglyph   ? StereoMode::SideBySide
                           : view_.stereo == StereoMode::SideBySide ? StereoMode::QuadBuffer
                                                                    : StereoMode::Off;
            if (view_.stereo == StereoMode::QuadBuffer && !view_.quadBufferAvailable)
                panel_.notice.say(
                    "no quad-buffer stereo on this display: showing anaglyph (start with --stereo quad on a "
                    "stereo-capable GPU)",
                    false);
            break;
        case GLFW_KEY_4: view_.eyeSeparation_m = std::max(0.0, view_.eyeSeparation_m * 0.9); break;
        case GLFW_KEY_5: view_.eyeSeparation_m = std::max(1e-4, view_.eyeSeparation_m * 1.1); break;
        case GLFW_KEY_6: view_.focalLength_m *= 0.9; break;
        case GLFW_KEY_7: view_.focalLength_m *= 1.1; break;
        case GLFW_KEY_R:
            session_.resetModel();
            plot_.clear();
            break;
        case GLFW_KEY_SPACE:
            paused_ = !paused_;
            session_.loop().commands().push(
                {paused_ ? haptics::LoopCommand::Kind::Pause : haptics::LoopCommand::Kind::Resume, 0});
            break;
        case GLFW_KEY_F: frameOrgan(); break;
        case GLFW_KEY_H: showHelp_ = !showHelp_; break;
        case GLFW_KEY_F1: showPanel_ = !showPanel_; break;
        case GLFW_KEY_ESCAPE:
        case GLFW_KEY_Q: glfwSetWindowShouldClose(window_->handle(), GLFW_TRUE); break;
        default: break;
    }
    (void)mods;
}

void Viewer::drawOverlay(const haptics::Snapshot& s) {
    const float left = showPanel_ ? panel_.rightEdge_px : 0.0f;
    drawNotice(panel_.notice, ImGui::GetTime(), left);
    if (!engagedOnce_ && !showHelp_ && session_.mouseDrives()) drawStartHint(session_.handCount() == 2, left);
    std::array<HandMark, haptics::kMaxHands> marks;
    const int count = std::min(s.handCount, static_cast<int>(marks.size()));
    for (int h = 0; h < count; ++h) {
        const haptics::HandStep& hand = s.hands[static_cast<std::size_t>(h)];
        marks[static_cast<std::size_t>(h)] = {hand.proxy_m, hand.force_N.norm(), hand.contact};
    }
    // ImGui draws in window coordinates, which differ from the framebuffer's on a scaled display.
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    drawForceMarks(std::span(marks.data(), static_cast<std::size_t>(count)), session_.scene().settings.maxForce_N,
                   view_.camera, view_.stereo, display.x, display.y);
    exercise_.draw(session_, panel_, view_.camera, view_.stereo, left, ImGui::GetTime());
}

void Viewer::onMouseButton(int button, int action, int mods) {
    const bool down = action == GLFW_PRESS;
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
        if (down && session_.mouseDrives()) {
            const haptics::Snapshot& s = session_.loop().snapshots().readLatest();
            const render::Ray ray = cursorRay();
            mouse_.engage(view_.camera, ray, pickSurface(ray, s.positions, s.faces));
            engagedOnce_ = true;
        } else if (!down) {
            mouse_.release();
        }
    } else if (button == GLFW_MOUSE_BUTTON_RIGHT) {
        if (down) mouse_.release();  // orbiting or panning moves the ray: let go, as for a view key
        orbiting_ = down && !(mods & GLFW_MOD_SHIFT);
        panning_ = down && (mods & GLFW_MOD_SHIFT);
    } else if (button == GLFW_MOUSE_BUTTON_MIDDLE) {
        if (down) mouse_.release();
        panning_ = down;
    }
    lastX_ = cursorX_;
    lastY_ = cursorY_;
}

void Viewer::onScroll(double dy) {
    if (mouse_.engaged())
        mouse_.push(dy);
    else
        view_.camera.zoom(dy);
}

void Viewer::onCursor(double x, double y) {
    cursorX_ = x;
    cursorY_ = y;
    const double dx = x - lastX_, dy = y - lastY_;
    if (orbiting_) view_.camera.orbit(-dx * 0.008, dy * 0.008);
    if (panning_) {
        const double perPixel = view_.camera.distance_m * 0.0015;
        view_.camera.pan(-dx * perPixel, dy * perPixel);
    }
    lastX_ = x;
    lastY_ = y;
}

void Viewer::updateDevice(const haptics::Snapshot& snapshot) {
    if (!session_.mouseDrives()) return;
    const render::Ray ray = cursorRay();
    Vec3 position;
    // A turned blade reports its orientation, handle up and towards the viewer as it is drawn, and the
    // cut follows where that line goes into the tissue: the wheel pushes the blade along it.
    if (mouse_.engaged())
        position =
            mouse_.drag(view_.camera, ray,
                        bladeTurned_ ? std::optional<Vec3>(-render::toolHandleDirection(view_.camera)) : std::nullopt);
    else
        position = mouse_.hover(view_.camera, ray, pickSurface(ray, snapshot.positions, snapshot.faces));
    if (bladeTurned_)
        session_.mouseDevice().setOrientation(
            Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), render::toolHandleDirection(view_.camera)) *
            Eigen::AngleAxisd(bladeTurn_deg_ * 3.14159265358979323846 / 180, Vec3::UnitZ()));
    const std::uint32_t mark = ImGui::GetTime() < markUntil_s_ ? 2u : 0u;
    session_.mouseDevice().setPosition(position, (mouse_.engaged() ? 1u : 0u) | mark);
}

int Viewer::run() {
    GLFWwindow* w = window_->handle();
    // The devices first: a missing one ends the run before the UI starts.
    // The command line's devices, or else the scene's [[devices]] with their tools and limits.
    std::vector<haptics::DeviceName> names;
    std::vector<scene::SceneDevice> fromScene;
    if (!options_.devicesGiven && !session_.scene().settings.devices.empty()) {
        fromScene = session_.scene().settings.devices;
        for (const scene::SceneDevice& d : fromScene) names.push_back(d.device);
    } else {
        for (const std::string& text : options_.devices)
            if (const auto spec = haptics::parseDeviceName(text)) names.push_back(*spec);  // checked by the command
    }
    const int hands = std::max(options_.hands, static_cast<int>(names.size()));
    if (hands > 1) session_.setHandCount(hands);
    for (std::size_t h = 0; h < fromScene.size(); ++h) {
        session_.setHandSettings(static_cast<int>(h), fromScene[h]);
        if (const auto tool = session_.scene().toolIndex(fromScene[h].tool)) {
            session_.setActiveHand(static_cast<int>(h));
            session_.setTool(*tool);
        }
    }
    session_.setActiveHand(0);
    if (!fromScene.empty()) session_.restartLoop();  // with each hand's limits and coupling
    for (std::size_t h = 0; h < names.size(); ++h) {
        const haptics::DeviceName* spec = &names[h];
        if (spec->kind == haptics::DeviceKind::Virtual) continue;  // the mouse
        scene::DeviceOptions deviceOptions;
        deviceOptions.fitWorkspace = options_.fitWorkspace;
        if (h < fromScene.size()) deviceOptions = scene::deviceOptionsFor(fromScene[h], options_.fitWorkspace, "");
        auto opened = scene::openDeviceFor(session_.scene(), *spec, deviceOptions);
        if (!opened) {
            std::cerr << "hapticut view: " << opened.error().toString() << "\n";
            return 1;
        }
        std::cerr << "hapticut view: hand " << h + 1 << ": " << opened->description << "\n";
        session_.useDevice(std::move(opened->device), static_cast<int>(h));
        if (!session_.loopError().empty()) {
            std::cerr << "hapticut view: " << session_.loopError() << "\n";
            return 1;
        }
    }
    if (!options_.trajectory.empty()) {
        if (const auto error = session_.replay(options_.trajectory)) {
            std::cerr << error->toString() << "\n";
            return 1;
        }
    }
    glfwSetWindowUserPointer(w, this);
    // Ours first; ImGui's backend chains to them, and we skip what ImGui wants for itself.
    glfwSetKeyCallback(w, [](GLFWwindow* win, int key, int, int action, int mods) {
        if (action == GLFW_PRESS && !ImGui::GetIO().WantCaptureKeyboard) of(win).onKey(key, mods);
    });
    glfwSetMouseButtonCallback(w, [](GLFWwindow* win, int button, int action, int mods) {
        if (action == GLFW_PRESS && ImGui::GetIO().WantCaptureMouse) return;
        of(win).onMouseButton(button, action, mods);
    });
    glfwSetScrollCallback(w, [](GLFWwindow* win, double, double dy) {
        if (!ImGui::GetIO().WantCaptureMouse) of(win).onScroll(dy);
    });
    glfwSetCursorPosCallback(w, [](GLFWwindow* win, double x, double y) { of(win).onCursor(x, y); });

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the user's folder
    ImGui::StyleColorsDark();
    // Thin, see-through slider grabs: the value is printed across the slider and a solid grab hid digits.
    ImGui::GetStyle().GrabMinSize = 4;
    ImGui::GetStyle().Colors[ImGuiCol_SliderGrab] = ImVec4(0.45f, 0.7f, 1.0f, 0.55f);
    ImGui::GetStyle().Colors[ImGuiCol_SliderGrabActive] = ImVec4(0.6f, 0.8f, 1.0f, 0.8f);
    ImGui_ImplGlfw_InitForOpenGL(w, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");
    glfwSwapInterval(options_.frames >= 0 ? 0 : 1);  // scripted runs measure the frame rate, unthrottled

    if (exercise_.active()) {  // an exercise: recorded from the start, to --record's file if given
        exercise_.start(session_, panel_, ImGui::GetTime());
        if (!session_.recording()) {
            std::cerr << "hapticut view: cannot record the exercise's session to " << exercise_.sessionFile() << "\n";
            return 1;
        }
        panel_.recordPath = exercise_.sessionFile();
    } else if (!options_.record.empty()) {  // --record: from the first step
        if (const Status failed = session_.startRecording(options_.record)) {
            std::cerr << "hapticut view: " << failed->toString() << "\n";
            return 1;
        }
        panel_.recordPath = options_.record;
    }
    long frames = 0;
    int fbw = 0, fbh = 0;
    const auto start = Clock::now();
    auto rateClock = start;
    long rateFrames = 0, rateStep = session_.loop().snapshots().readLatest().step;
    Rates rates;
    const auto timeIsUp = [&] {
        return options_.quitAfter_s >= 0 &&
               std::chrono::duration<double>(Clock::now() - start).count() >= options_.quitAfter_s;
    };
    // Ctrl-C or SIGTERM closes the window like q: the loop stops and every device is left at zero force.
    const StopSignal stopSignal;
    bool lastFrame = false;  // decided before the frame is drawn, so that --screenshot captures it
    while (!lastFrame && !glfwWindowShouldClose(w) && (options_.frames < 0 || frames < options_.frames) &&
           !StopSignal::requested()) {
        lastFrame = timeIsUp() || (options_.frames >= 0 && frames + 1 == options_.frames);
        glfwPollEvents();
        if (session_.scene().source.name != framedModel_) frameOrgan();  // a model loaded from the panel
        view_.camera.centreX_ndc = freeViewCentre();                     // the panel shown, hidden (F1) or moved
        while (renderer_->toolCount() < session_.scene().tools.size())
            renderer_->addTool(session_.scene().tools[renderer_->toolCount()].mesh);
        exercise_.update(session_, panel_, ImGui::GetTime());
        const haptics::Snapshot& s = session_.loop().snapshots().readLatest();
        updateDevice(s);
        const double t_s = std::chrono::duration<double>(Clock::now() - start).count();
        const haptics::HandStep& hand =
            s.hands[static_cast<std::size_t>(std::min(session_.activeHand(), s.handCount - 1))];
        plot_.add(t_s, hand.force_N);

        // A reset (from a key or the panel) starts a new organ whose topology versions count from zero again.
        if (session_.resets() != drawnResets_) {
            renderer_->invalidateOrgan();
            drawnResets_ = session_.resets();
        }
        const auto tools = session_.toolsInHands();
        const render::SceneFrame frame = render::frameOf(s, tools, session_.scene().settings.maxForce_N);
        glfwGetFramebufferSize(w, &fbw, &fbh);
        renderer_->draw(frame, view_, fbw, fbh);

        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        if (showPanel_) drawPanel(session_, view_, s, rates, plot_, panel_);
        if (showHelp_) drawHelp();
        drawOverlay(s);
        if (!showPanel_ && !showHelp_) {
            ImGui::SetNextWindowPos(ImVec2(10, 10));
            ImGui::SetNextWindowBgAlpha(0.5f);
            ImGui::Begin("##rates", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize);
            ImGui::Text("%.0f fps  %.0f Hz  |F| %.2f N   h: keys", rates.renderFps, rates.hapticRate_hz,
                        hand.force_N.norm());
            ImGui::End();
        }
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

        ++frames;
        ++rateFrames;
        const double since = std::chrono::duration<double>(Clock::now() - rateClock).count();
        if (since >= 0.5) {
            rates.renderFps = static_cast<double>(rateFrames) / since;
            // A reset starts a new loop whose steps count from zero again.
            rates.hapticRate_hz = static_cast<double>(s.step >= rateStep ? s.step - rateStep : s.step) / since;
            rateClock = Clock::now();
            rateFrames = 0;
            rateStep = s.step;
        }
        if (lastFrame && !options_.screenshot.empty()) {
            glFinish();
            if (const auto error = render::savePng(options_.screenshot, render::readWindow(fbw, fbh))) {
                std::cerr << "hapticut view: " << *error << "\n";
                return 1;
            }
            std::cout << "wrote the last frame to " << options_.screenshot << "\n";
        }
        glfwSwapBuffers(w);
    }
    glFinish();
    if (session_.recording()) {  // the window closed while recording: keep what was recorded
        finishRecording(session_, panel_);
        std::cout << panel_.notice.text << "\n";
    }
    const double wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    const haptics::Snapshot& last = session_.loop().snapshots().readLatest();
    const double fps = static_cast<double>(frames) / std::max(wall_s, 1e-9);
    std::cout << "rendered " << frames << " frames in " << wall_s << " s: " << fps << " fps ("
              << window_->rendererDescription() << "); haptic loop " << last.step << " steps, " << last.overruns
              << " overruns; haptic thread " << session_.hapticScheduling() << "\n";
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    if (!options_.report.empty()) {
        nlohmann::ordered_json j;
        j["model"] = session_.scene().source.name;
        j["faces"] = last.faces.size();
        j["size"] = {fbw, fbh};
        j["stereo"] = render::stereoModeName(view_.stereo);
        j["frames"] = frames;
        j["wall_time_s"] = wall_s;
        j["fps"] = fps;
        j["haptic_steps"] = last.step;
        j["haptic_rate_hz"] = static_cast<double>(last.step) / std::max(wall_s, 1e-9);
        j["overruns"] = last.overruns;
        j["stalls"] = last.stalls;
        // The cut counts are since the model was last reset (r) or loaded, which undoes every cut.
        j["model_resets"] = session_.resets() - 1;  // the first load counts as one
        j["cut_events"] = last.cutEvents;
        j["cuts"] = last.cut.cuts;
        j["cut_points"] = last.cut.cutPoints;
        j["cut_length_m"] = last.cut.length_m;
        j["wounds_crossed"] = last.cut.woundsCrossed;
        j["joins"] = last.cut.joins;
        j["openings"] = last.cut.openings;
        j["walls_closed"] = last.cut.wallsClosed;
        j["renderer"] = window_->rendererDescription();
        j["renderer_threads_yielding"] = yieldingThreads;
        j["haptic_thread_scheduling"] = session_.hapticScheduling();
        j["provenance"] = app::provenance();
        if (const auto error = writeTextFileAtomically(options_.report, j.dump(2) + "\n")) {
            std::cerr << error->toString() << "\n";
            return 1;
        }
        std::cout << "wrote the report to " << options_.report << "\n";
    }
    return 0;
}

}  // namespace

int runViewer(const ViewerOptions& options) {
    auto scene = scene::loadScene(options.scene);
    if (!scene) {
        std::cerr << scene.error().toString() << "\n";
        return 1;
    }
    for (const Warning& w : scene->source.warnings) std::cerr << "warning: " << w.toString() << "\n";
    if (!scene->toolIndex(options.tool)) {
        std::cerr << "hapticut view: unknown tool '" << options.tool << "': the scene has";
        for (const scene::Tool& t : scene->tools) std::cerr << " " << t.name;
        std::cerr << "\n";
        return 2;
    }
    render::WindowOptions windowOptions;
    windowOptions.width = options.width;
    windowOptions.fitToMonitor = !options.sizeGiven;
    windowOptions.height = options.height;
    windowOptions.fullscreen = options.fullscreen;
    windowOptions.quadStereo = options.stereo == render::StereoMode::QuadBuffer;
    windowOptions.title = "Hapticut: " + scene->source.name;
    std::string error;
    auto window = render::GlWindow::open(windowOptions, error);
    if (!window) {
        std::cerr << "hapticut view: " << error << "\n";
        return 1;
    }
    if (windowOptions.quadStereo && !window->hasQuadStereo())
        std::cerr << "hapticut view: this display offers no quad-buffer stereo; showing anaglyph (red-cyan) instead\n";
    std::vector<mesh::SurfaceMesh> tools;
    for (const scene::Tool& t : scene->tools) tools.push_back(t.mesh);
    auto renderer = render::Renderer::create(tools, error);
    if (!renderer) {
        std::cerr << "hapticut view: " << error << " (" << window->rendererDescription() << ")\n";
        return 1;
    }
    renderer->setOrganRims(scene->source.mesh.faces);
    // The driver's threads exist now and ours do not yet: they yield to the haptic loop from here on.
    const std::vector<std::string> yielding = deprioritiseOtherThreads(kRendererNiceness);
    Viewer viewer(options, std::move(window), std::move(renderer), std::move(*scene));
    viewer.yieldingThreads = yielding;
    return viewer.run();
}

}  // namespace hapticut::viewer
