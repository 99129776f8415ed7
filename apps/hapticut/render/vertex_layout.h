// The renderer's one vertex layout, shared by the organ, the tools and the markers.
#pragma once

namespace hapticut::render {

/// Position xyz, normal xyz, uv, and how much the vertex lies on a wound's lip (0 or 1).
inline constexpr int kFloatsPerVertex = 9;

}  // namespace hapticut::render
