// Occlusion culling: what it hides is hidden, so frames are the same with and without it.
#include <doctest/doctest.h>

#include "render/occlusion.hpp"
#include "render/render_support.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::render;

namespace {

// A block of 8 x 8 x 8 spheres on a cubic lattice, with gravity along -z.
const char* kBlock = R"(
[scene]
dimension = 3
[domain]
lo = [-1, -1, -1]
hi = [9, 9, 9]
[gravity]
magnitude = 1.0
[contact]
model = "hooke"
k_n = 1000
[[grains]]
radius = 0.49
placement = "lattice"
lattice = "sc"
spacing = 1.0
region_lo = [0, 0, 0]
region_hi = [8, 8, 8]
[run]
dt = 1e-3
)";

}  // namespace

TEST_CASE("occlusion culling hides the grains and chains inside a block, and the frame stays the same") {
  auto sim = test::simulation_from(kBlock);
  REQUIRE(sim->state().n == 512);
  View v = test::plain_view(480, 320, {"grains"});
  v.color_by = "id";
  RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  // A chain through the middle of the block, and one beside it in the open.
  rs.segments.push_back({{3.5f, 3.5f, 3.5f}, {4.5f, 3.5f, 3.5f}, 0.3f, Rgba{255, 0, 0, 255}});
  rs.segments.push_back({{8.6f, 3.0f, 4.0f}, {8.6f, 4.0f, 4.0f}, 0.3f, Rgba{255, 0, 0, 255}});  // the camera's side
  const Hidden h = find_hidden(rs);
  int hidden = 0;
  for (char c : h.spheres) hidden += c;
  CAPTURE(hidden);
  CHECK(hidden > 216);  // the inside of the block (6 x 6 x 6) and some of the far side
  CHECK(h.segments[0] == 1);
  CHECK(h.segments[1] == 0);
  // The outermost grains facing the camera are never hidden: the one nearest to the eye.
  size_t nearest = 0;
  double best = 1e300;
  for (size_t k = 0; k < rs.spheres.size(); ++k) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) d2 += std::pow(rs.spheres[k].centre[a] - rs.camera.eye[a], 2);
    if (d2 < best) best = d2, nearest = k;
  }
  CHECK(h.spheres[nearest] == 0);
  Rasterizer raster(1);
  const Image culled = raster.draw(rs);
  rs.cull_hidden = false;
  const Image all = raster.draw(rs);
  CHECK(culled.rgba == all.rgba);
  // Translucent grains hide nothing; an orthographic frame is never culled.
  for (auto& s : rs.spheres) s.color.a = 128;
  int translucent_hidden = 0;
  for (char c : find_hidden(rs).spheres) translucent_hidden += c;
  CHECK(translucent_hidden == 0);
  rs.camera.ortho = true;
  CHECK(find_hidden(rs).segments[0] == 0);
}

TEST_CASE("occlusion culling: a grain behind a larger one is hidden, one beside it is not") {
  auto sim = test::simulation_from(R"(
[scene]
dimension = 3
[domain]
lo = [-6, -6, -6]
hi = [6, 6, 6]
[contact]
model = "hooke"
k_n = 1000
[[grains]]
radius = 2.0
placement = "explicit"
positions = [[0, 0, 3]]
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[0, 0, -1], [4, 0, -1]]
[run]
dt = 1e-3
)");
  View v = test::plain_view(400, 400, {"grains"});
  v.elevation = 89;  // looking down z: the big grain in front of the small one below it
  v.target_auto = false;
  v.distance = 30;
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  const Hidden h = find_hidden(rs);
  CHECK(h.spheres == std::vector<char>{0, 1, 0});
  Rasterizer raster(1);
  RenderScene all = rs;
  all.cull_hidden = false;
  CHECK(raster.draw(rs).rgba == raster.draw(all).rgba);
}

TEST_CASE("occlusion culling: a grain projected far beyond the frame is handled without overflow") {
  auto sim = test::simulation_from(kBlock);
  View v = test::plain_view(64, 48, {"grains"});
  RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  // Its screen rectangle spans some 1e37 pixels: tile indices beyond any int (UBSan found the
  // conversion, from a shell session).
  rs.spheres[0].centre = {3e38f, 3e38f, 4.0f};
  rs.spheres[1].centre = {-3e38f, 4.0f, 3e38f};
  const Hidden h = find_hidden(rs);
  REQUIRE(h.spheres.size() == rs.spheres.size());
  Rasterizer raster(1);
  const Image culled = raster.draw(rs);
  rs.cull_hidden = false;
  CHECK(culled.rgba == raster.draw(rs).rgba);
}
