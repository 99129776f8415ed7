// The renderer's one vertex layout, shared by the organ, the tools and the markers.
#pragma once

namespace hapticut::render {

/// Position xyz, normal xyz, uv, and the wound attribute: 0 tissue, 1 on a wound's lip, 2 a wound's wall.
inline constexpr int kFloatsPerVertex = 9;

}  // namespace hapticut::render
