// What the haptic loop published, as a frame for the renderer (the viewer and the frame-rate benchmark).
#pragma once

#include <algorithm>
#include <span>

#include "hapticut/haptics/haptic_loop.h"
#include "render/renderer.h"

namespace hapticut::render {

/// The frame's spans point into `s`, which must stay unchanged until the draw. `tools` holds the tool in
/// each hand (indices into the renderer's tools).
inline SceneFrame frameOf(const haptics::Snapshot& s, std::span<const int> tools, double maxForce_N) {
    SceneFrame frame;
    frame.organPositions = s.positions;
    frame.faces = s.faces;
    frame.uvs = s.uvs;
    frame.wallFaces = s.wallFaces;
    frame.topologyVersion = s.topologyVersion;
    frame.handCount = std::min({s.handCount, static_cast<int>(frame.hands.size()), static_cast<int>(tools.size())});
    for (std::size_t h = 0; h < static_cast<std::size_t>(frame.handCount); ++h) {
        SceneFrame::Hand& hand = frame.hands[h];
        hand.tool = tools[h];
        hand.proxy_m = s.hands[h].proxy_m;
        hand.device_m = s.hands[h].device_m;
        hand.force_N = s.hands[h].force_N;
        hand.contact = s.hands[h].contact;
        hand.orientation = s.hands[h].orientation;
        hand.oriented = s.hands[h].oriented;
    }
    frame.maxForce_N = maxForce_N;
    return frame;
}

}  // namespace hapticut::render
