// Occlusion culling of a perspective frame (no GL): the grains and chains of a dense 3D bed that
// opaque grains nearer to the eye hide wholly, so the rasterizer need not shade them.
#pragma once

#include <vector>

#include "silt/render.hpp"

namespace silt::render {

// Flags (1: hidden) for scene.spheres and scene.segments; all 0 for an orthographic camera.
// Conservative: whatever is flagged would leave no pixel in the frame.
struct Hidden {
  std::vector<char> spheres, segments;
};
Hidden find_hidden(const RenderScene& scene);

}  // namespace silt::render
