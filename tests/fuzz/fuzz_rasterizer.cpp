// The rasterizer of the session targets: defines what render/rasterizer.cpp does (which the linker
// then leaves out of the static render library), without GL. A new OSMesa context and its
// shaders take about 40 ms under the sanitizers, in every session that draws: most of such an
// input's time, and none of it silt's logic. What silt computes for a frame is still done: the
// render scene (by the caller), the occlusion culling here, then the overlays and the PNG file.
#include <cstdint>

#include "render/occlusion.hpp"
#include "silt/render.hpp"

namespace silt::render {

struct Rasterizer::Impl {};

Rasterizer::Rasterizer(int) : impl_(std::make_unique<Impl>()) {}
Rasterizer::~Rasterizer() = default;

Image Rasterizer::draw(const RenderScene& scene) {
  if (scene.cull_hidden) (void)find_hidden(scene);
  Image img;
  img.width = scene.width;
  img.height = scene.height;
  img.rgba.resize(static_cast<size_t>(scene.width) * scene.height * 4);
  for (size_t k = 0; k < img.rgba.size(); k += 4) {
    img.rgba[k] = scene.background.r;
    img.rgba[k + 1] = scene.background.g;
    img.rgba[k + 2] = scene.background.b;
    img.rgba[k + 3] = 255;
  }
  return img;
}

}  // namespace silt::render
