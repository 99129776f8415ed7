// Frames per second of the renderer on the procedural heart, with the haptic loop pressing it in its
// own thread, offscreen at a given size, mono or stereo (the thesis's table, SPEC "Measurements").
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "render/stereo.h"

namespace hapticut::bench {

struct FrameRateCase {
    int triangles = 1619;
    int width = 1280, height = 1024;
    render::StereoMode stereo = render::StereoMode::Off;
};

struct FrameRateResult {
    FrameRateCase what;
    int faces = 0;  // the heart's actual triangle count
    long frames = 0;
    double fps = 0;
    double hapticRate_hz = 0;  // the loop's steps per second while the frames were drawn
};

/// Each case for at least `seconds`; frames are finished (glFinish), so the rate is the GPU's too.
/// Nothing, with `error`, when no GL context opens. `renderer` receives the GL renderer's name.
bool measureFrameRates(const std::vector<FrameRateCase>& cases, double seconds, std::vector<FrameRateResult>& results,
                       std::string& renderer, std::string& error,
                       const std::function<void(const FrameRateResult&)>& onResult = {});

}  // namespace hapticut::bench
