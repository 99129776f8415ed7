// `hapticut view`: the interactive window (SPEC R18-R20, appendix A).
#pragma once

#include <string>
#include <vector>

#include "hapticut/scene/scene.h"
#include "render/stereo.h"

namespace hapticut::viewer {

struct ViewerOptions {
    scene::SceneRequest scene;
    render::StereoMode stereo = render::StereoMode::Off;
    bool fullscreen = false;
    int width = 1280, height = 1024;
    bool sizeGiven = false;   // --size: exactly that; otherwise at most the monitor's work area
    long frames = -1;         // quit after this many frames (scripted runs, benchmarks); negative: until closed
    double quitAfter_s = -1;  // quit after this long on the wall clock; negative: until closed
    std::string screenshot;   // with frames: the last frame, panel and all, as a PNG
    std::string trajectory;   // replay this device path instead of following the mouse
    std::string tool = "probe";
    std::vector<std::string> devices{
        "virtual"};             // one per hand: virtual (the mouse), replay:FILE, openhaptics[:NAME], sdl[:INDEX]
    bool devicesGiven = false;  // --device was given: it replaces the scene's [[devices]]
    int hands = 1;              // two: a second hand (Tab switches the one the mouse drives)
    bool fitWorkspace = true;   // fit each hardware device's reach to the organ
    std::string report;         // JSON: frames, frame rate, haptic rate, renderer
    std::string record;         // the active hand's device path at the loop's rate (Simulation::startRecording)
    bool wireframe = false;
    bool hidePanel = false;
};

/// Runs the viewer until the window closes (or `frames` are drawn); the exit code.
int runViewer(const ViewerOptions& options);

}  // namespace hapticut::viewer
