// The panel: what the loop is doing, the tool, the device, the material, the files.
#include "viewer/panel.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <string>

#include "hapticut/common/text_file.h"
#include "hapticut/haptics/openhaptics_device.h"
#include "hapticut/haptics/step_log.h"

namespace hapticut::viewer {

const std::vector<KeyHelp> kKeyHelp = {
    {"1 / 2", "hold the probe / the scalpel"},
    {"[ / ]", "turn the scalpel's blade 15 degrees about its handle: it cuts the way its edge faces"},
    {"left drag", "engage the device at the surface and move it (press, stroke, cut)"},
    {"wheel (engaged)", "push the device in / pull it out, 1 mm a click"},
    {"right drag", "orbit the camera"},
    {"middle drag, shift+right", "pan the camera"},
    {"wheel", "zoom"},
    {"w", "wireframe on/off (R18)"},
    {"b", "bump mapping on/off"},
    {"s", "stereo: off, anaglyph, side-by-side, quad buffer"},
    {"4 / 5", "eye separation down / up"},
    {"6 / 7", "focal length down / up"},
    {"m", "mark where a lump is (a palpation exercise), like a stylus's second button"},
    {"r", "reset the model (undo every cut)"},
    {"space", "pause / resume the physics"},
    {"f", "frame the organ"},
    {"Tab", "with two hands (--hands 2): switch the hand the mouse drives"},
    {"h", "this help"},
    {"F1", "the panel"},
    {"Esc, q", "quit"},
};

void drawHelp() {
    ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x * 0.5f, ImGui::GetIO().DisplaySize.y * 0.5f),
                            ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowBgAlpha(0.85f);
    ImGui::Begin("Keys", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse);
    if (ImGui::BeginTable("keys", 2)) {
        for (const KeyHelp& k : kKeyHelp) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextColored(ImVec4(1, 0.85f, 0.4f, 1), "%s", k.key);
            ImGui::TableSetColumnIndex(1);
            ImGui::TextUnformatted(k.what);
        }
        ImGui::EndTable();
    }
    ImGui::End();
}

namespace {

void section(const char* title) {
    ImGui::Spacing();
    ImGui::Separator();
    ImGui::TextColored(ImVec4(1, 0.85f, 0.4f, 1), "%s", title);
}

void materialSlider(scene::Simulation& session, const char* label, scene::MaterialKnob knob) {
    float scale = static_cast<float>(session.materialScale(knob));
    if (ImGui::SliderFloat(label, &scale, 0.1f, 10.0f, "x %.2f", ImGuiSliderFlags_Logarithmic))
        session.setMaterialScale(knob, scale);
}

void loopSection(scene::Simulation& session, const haptics::Snapshot& s, const Rates& rates) {
    ImGui::Text("render %.0f fps   haptic %.0f Hz", rates.renderFps, rates.hapticRate_hz);
    ImGui::Text("haptic thread: %s", session.hapticScheduling().c_str());
    ImGui::Text("step %.1f us (max %.1f us)", s.stepTime_us, s.maxStepTime_us);
    if (s.multiRate) {
        ImGui::Text("physics %.0f Hz on its own thread (multi-rate)", s.physicsRate_hz);
        ImGui::Text("  %.3f of real time, last step %.1f ms", s.physicsRealtimeFactor, s.physicsStep_s * 1e3);
    }
    if (s.scheme == physics::Scheme::BackwardEuler)
        ImGui::Text("implicit, %d CG iterations (%s)", s.solverIterations,
                    s.solverMultilevel ? "multilevel" : "block-Jacobi");
    else
        ImGui::Text("%s, %d substep%s (stable below %.2f ms)", std::string(physics::schemeName(s.scheme)).c_str(),
                    s.substeps, s.substeps == 1 ? "" : "s", s.stableStep_s * 1e3);
    ImGui::Text("overruns %ld   cut events %ld", s.overruns, s.cutEvents);
    if (s.cut.cuts > 0)
        ImGui::Text("%ld cut%s, %.1f mm long, %ld earlier wound%s cut through", s.cut.cuts, s.cut.cuts == 1 ? "" : "s",
                    s.cut.length_m * 1e3, s.cut.woundsCrossed, s.cut.woundsCrossed == 1 ? "" : "s");
    if (s.stalls > 0)  // gaps of 3 periods or more, after each of which the force sent ramped back in
        ImGui::TextColored(ImVec4(1, 0.7f, 0.2f, 1), "stalls %ld: force ramped back in", s.stalls);
    if (s.watchdogTripped) {
        ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "watchdog tripped: force is zero");
        ImGui::SameLine();
        if (ImGui::SmallButton("reset")) session.loop().commands().push({haptics::LoopCommand::Kind::ResetWatchdog, 0});
    }
    if (s.paused) ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "physics paused (space)");
    haptics::LoopConfig& c = session.config();
    int scheme = static_cast<int>(c.scheme);
    // In the order of physics::Scheme.
    const char* schemes[] = {"euler", "midpoint", "rk4", "symplectic", "implicit", "auto"};
    bool restart = ImGui::Combo("integrator", &scheme, schemes, 6);
    float rate = static_cast<float>(c.rate_hz);
    ImGui::SliderFloat("loop rate", &rate, 250.0f, 4000.0f, "%.0f Hz", ImGuiSliderFlags_Logarithmic);
    restart |= ImGui::IsItemDeactivatedAfterEdit();
    if (restart) {
        c.scheme = static_cast<physics::Scheme>(scheme);
        c.rate_hz = rate;
        session.restartLoop();
    }
}

}  // namespace

void finishRecording(scene::Simulation& session, PanelState& state) {
    if (!session.recording()) return;
    const std::string file = session.recordingFile();
    const long rows = session.recordedSteps(), dropped = session.droppedRecordingSteps();
    const std::vector<Error> errors = session.stopRecording();
    state.notice.say(!errors.empty() ? errors.front().toString()
                                     : "wrote " + std::to_string(rows) + " steps to " + file +
                                           (dropped > 0 ? " (" + std::to_string(dropped) + " dropped)" : ""),
                     !errors.empty());
}

void drawPanel(scene::Simulation& session, render::ViewSettings& view, const haptics::Snapshot& s, const Rates& rates,
               const ForcePlot& plot, PanelState& state) {
    ImGui::SetNextWindowPos(ImVec2(kPanelLeft_px, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(kPanelWidth_px, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin("Hapticut");
    state.rightEdge_px = ImGui::GetWindowPos().x + ImGui::GetWindowSize().x;
    loopSection(session, s, rates);

    section("Force");
    for (int h = 0; h < s.handCount; ++h) {
        const haptics::HandStep& hand = s.hands[static_cast<std::size_t>(h)];
        ImGui::Text("%s|F| %.2f N  (%.2f, %.2f, %.2f)  %s", s.handCount > 1 ? (h == 0 ? "right  " : "left   ") : "",
                    hand.force_N.norm(), hand.force_N.x(), hand.force_N.y(), hand.force_N.z(),
                    hand.cutting   ? "cutting"
                    : hand.contact ? "contact"
                                   : "free");
    }
    plot.draw(session.scene().settings.maxForce_N, ImGui::GetContentRegionAvail().x, 110);

    section("Hands");
    bool two = session.handCount() == 2;
    if (ImGui::Checkbox("two hands", &two)) session.setHandCount(two ? 2 : 1);
    if (session.handCount() == 2) {
        ImGui::SameLine();
        int active = session.activeHand();
        ImGui::RadioButton("right", &active, 0);
        ImGui::SameLine();
        ImGui::RadioButton("left", &active, 1);
        ImGui::SameLine();
        ImGui::TextDisabled("(Tab)");
        session.setActiveHand(active);
    }

    section(session.handCount() == 2 ? (session.activeHand() == 0 ? "Tool in the right hand" : "Tool in the left hand")
                                     : "Tool");
    const auto& tools = session.scene().tools;
    for (std::size_t i = 0; i < tools.size(); ++i) {
        if (i) ImGui::SameLine();
        if (ImGui::RadioButton(tools[i].name.c_str(), session.tool() == i)) session.setTool(i);
    }
    haptics::LoopConfig& c = session.config();
    float threshold = static_cast<float>(std::min(session.cutThreshold(), 100.0));
    if (ImGui::SliderFloat("cut threshold", &threshold, 0.2f, 100.0f, threshold >= 100 ? "never cuts" : "%.2f N",
                           ImGuiSliderFlags_Logarithmic))
        session.setCutThreshold(threshold >= 100 ? 1e9 : threshold);

    section("Device");
    if (session.replaying()) ImGui::Text("replaying %s", session.replayFile().c_str());
    if (const auto* hd = dynamic_cast<const haptics::OpenHapticsDevice*>(session.hardwareDevice())) {
        ImGui::Text("%s (%s), servo %.0f Hz, max %.1f N", hd->model().c_str(), hd->serial().c_str(), hd->servoRate_hz(),
                    hd->maxForce_N());
        if (hd->faulted()) ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "device fault: %s", hd->faultMessage().c_str());
    }
    float k = static_cast<float>(c.couplingStiffness_N_per_m);
    if (ImGui::SliderFloat("stiffness k_h", &k, 10.0f, 2000.0f, "%.0f N/m", ImGuiSliderFlags_Logarithmic)) {
        c.couplingStiffness_N_per_m = k;
        session.loop().commands().push({haptics::LoopCommand::Kind::SetCouplingStiffness, k});
    }
    if (ImGui::IsItemDeactivatedAfterEdit())
        session.restartLoop();  // a stiffer coupling needs the stable step prepared for it
    float b = static_cast<float>(c.couplingDamping_Ns_per_m);
    if (ImGui::SliderFloat("damping b_h", &b, 0.0f, 3.0f, "%.2f Ns/m")) {
        c.couplingDamping_Ns_per_m = b;
        session.loop().commands().push({haptics::LoopCommand::Kind::SetCouplingDamping, b});
    }
    if (ImGui::SliderFloat("max force", &state.maxForceScale, 0.0f, 1.0f, "%.2f of the device's"))
        session.loop().commands().push({haptics::LoopCommand::Kind::SetMaxForceScale, state.maxForceScale});

    section("Tissue (x the scene's values)");
    materialSlider(session, "mass", scene::MaterialKnob::Mass);
    materialSlider(session, "structural k", scene::MaterialKnob::StructuralStiffness);
    materialSlider(session, "structural d", scene::MaterialKnob::StructuralDamping);
    materialSlider(session, "positioning k", scene::MaterialKnob::PositioningStiffness);
    materialSlider(session, "positioning d", scene::MaterialKnob::PositioningDamping);

    section("View");
    ImGui::Checkbox("wireframe (w)", &view.wireframe);
    ImGui::SameLine();
    ImGui::Checkbox("bump mapping (b)", &view.normalMapping);
    ImGui::Checkbox("wound walls", &view.woundWalls);
    int stereo = static_cast<int>(view.stereo);
    const char* modes[] = {"off", "quad buffer", "anaglyph", "side by side"};
    if (ImGui::Combo("stereo (s)", &stereo, modes, 4)) view.stereo = static_cast<render::StereoMode>(stereo);
    float separation = static_cast<float>(view.eyeSeparation_m * 1e3),
          focal = static_cast<float>(view.focalLength_m * 1e3);
    if (ImGui::SliderFloat("eye separation", &separation, 0.0f, 60.0f, "%.1f mm"))
        view.eyeSeparation_m = separation * 1e-3;
    if (ImGui::SliderFloat("focal length", &focal, 20.0f, 2000.0f, "%.0f mm", ImGuiSliderFlags_Logarithmic))
        view.focalLength_m = focal * 1e-3;

    section("Files");
    ImGui::InputText("##model", &state.modelPath);
    ImGui::SameLine();
    if (ImGui::Button("load model")) {
        const auto error = session.loadModel(state.modelPath);
        state.notice.say(error ? error->toString() : "loaded " + state.modelPath, error.has_value());
    }
    ImGui::InputText("##tool", &state.toolPath);
    ImGui::SameLine();
    if (ImGui::Button("load tool")) {
        const auto error = session.loadTool(state.toolPath);
        state.notice.say(error ? error->toString() : "holding " + state.toolPath, error.has_value());
    }
    ImGui::InputText("##export", &state.exportPath);
    ImGui::SameLine();
    if (ImGui::Button("export mesh")) {
        const auto error = session.exportMesh(state.exportPath, s);
        state.notice.say(error ? error->toString() : "wrote " + state.exportPath, error.has_value());
    }
    ImGui::InputText("##record", &state.recordPath);
    ImGui::SameLine();
    if (!session.recording() && ImGui::Button("record")) {
        const Status failed = session.startRecording(state.recordPath);
        state.notice.say(failed ? failed->toString() : "recording the device path at the loop's rate",
                         failed.has_value());
    } else if (session.recording() && ImGui::Button("stop")) {
        finishRecording(session, state);
    }
    ImGui::InputText("##replay", &state.replayPath);
    ImGui::SameLine();
    if (ImGui::Button(session.replaying() ? "mouse" : "replay")) {
        if (session.replaying()) {
            session.useMouse();
        } else {
            const auto error = session.replay(state.replayPath);
            state.notice.say(error ? error->toString() : "replaying " + state.replayPath, error.has_value());
        }
    }
    if (ImGui::Button("reset model (r)")) session.resetModel();
    ImGui::End();
}

}  // namespace hapticut::viewer
