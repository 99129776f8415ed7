// The Dear ImGui panel (live tuning, rates, forces, files) and the help overlay listing every key.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/step_log.h"
#include "hapticut/scene/simulation.h"
#include "render/renderer.h"
#include "viewer/force_plot.h"
#include "viewer/overlay.h"

namespace hapticut::viewer {

struct Rates {
    double renderFps = 0;
    double hapticRate_hz = 0;
};

/// Where the panel first opens and how wide: at the window's left.
inline constexpr float kPanelLeft_px = 10, kPanelWidth_px = 380;

/// What the panel keeps between frames: text fields, a recording, the last message.
struct PanelState {
    std::string modelPath, toolPath, exportPath = "heart-cut.obj", replayPath, recordPath = "recording.csv";
    Notice notice;            // shown over the scene (overlay.h), so it is read wherever the panel is scrolled
    float maxForceScale = 1;  // of the device's maximum force
    // Where the panel ends, so the overlay and the organ centre in the view beside it (as the panel first
    // opens until it is drawn).
    float rightEdge_px = kPanelLeft_px + kPanelWidth_px;
};

/// Ends the session's recording, if one runs: its file is complete; what happened goes to state.notice.
void finishRecording(scene::Simulation& session, PanelState& state);

void drawPanel(scene::Simulation& session, render::ViewSettings& view, const haptics::Snapshot& snapshot,
               const Rates& rates, const ForcePlot& plot, PanelState& state);

struct KeyHelp {
    const char* key;
    const char* what;
};
/// Every key and mouse action of the viewer, as the help overlay (h) shows them.
extern const std::vector<KeyHelp> kKeyHelp;
void drawHelp();

}  // namespace hapticut::viewer
