// What the haptic loop published, as a frame for the renderer (the viewer and the frame-rate benchmark).
#pragma once

#include "hapticut/haptics/haptic_loop.h"
#include "render/renderer.h"

namespace hapticut::render {

/// The frame's spans point into `s`, which must stay unchanged until the draw.
inline SceneFrame frameOf(const haptics::Snapshot& s, int tool, double maxForce_N) {
    SceneFrame frame;
    frame.organPositions = s.positions;
    frame.faces = s.faces;
    frame.uvs = s.uvs;
    frame.topologyVersion = s.topologyVersion;
    frame.tool = tool;
    frame.proxy_m = s.proxy_m;
    frame.device_m = s.device_m;
    frame.force_N = s.force_N;
    frame.contact = s.contact;
    frame.maxForce_N = maxForce_N;
    return frame;
}

}  // namespace hapticut::render
