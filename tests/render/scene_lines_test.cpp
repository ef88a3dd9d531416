// Force chains (widths proportional to the force, their colour bar) and the box outline.
#include <doctest/doctest.h>

#include <cmath>
#include <sstream>

#include "render/render_support.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::render;
using silt::test::pixel_of;
using silt::test::white;

namespace {

// Twelve disks of radius 1 in a row, pressed together with overlaps (linear law, k_n = 1000, at
// rest, so F = k_n overlap): 0.02, 0.01, 0.04, 0.01, 0.08 and six more of 0.01. The mean is 0.02:
// contacts 0, 2 and 4 carry 1, 2 and 4 times the mean force.
const double kOverlaps[11] = {0.02, 0.01, 0.04, 0.01, 0.08, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01};

std::string row_scene() {
  std::ostringstream pos;
  double x = 1.5;
  for (int i = 0; i < 12; ++i) {
    pos << (i ? ", " : "") << "[" << x << ", 2]";
    if (i < 11) x += 2 - kOverlaps[i];
  }
  return R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [26, 4]
[contact]
model = "linear"
k_n = 1000
[[grains]]
radius = 1.0
placement = "explicit"
positions = [)" +
         pos.str() + R"(]
[run]
dt = 1e-3
)";
}

// Midpoint of contact k of the row.
double contact_x(const State& s, int k) { return 0.5 * (s.particle_x[2 * k] + s.particle_x[2 * k + 2]); }

// Length of the run of non-white pixels through `at` along the column.
int line_thickness(const Image& img, std::array<int, 2> at) {
  int n = 0;
  for (int y = 0; y < img.height; ++y) n += !white(img.pixel(at[0], y));
  return n;
}

}  // namespace

TEST_CASE("chain widths are proportional to the normal force: 1, 2 and 4 times the mean") {
  auto sim = test::simulation_from(row_scene());
  sim->prepare();
  View v = test::plain_view(1300, 200, {"chains"});
  RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(rs.segments.size() == 11);
  const auto& seg = rs.segments;
  CHECK(seg[0].width == doctest::Approx(0.4 * 1.0));  // chain_width 0.4 mean radii at the mean force
  CHECK(seg[2].width == doctest::Approx(2 * 0.4));
  CHECK(seg[4].width == doctest::Approx(4 * 0.4));
  CHECK(seg[1].width == doctest::Approx(0.5 * 0.4));
  // On screen: 40 pixels a unit, so 16, 32 and 64 pixels wide.
  Rasterizer raster(1);
  const Image img = raster.draw(rs);
  const State& s = sim->state();
  const int t1 = line_thickness(img, pixel_of(rs, contact_x(s, 0), 2)),
            t2 = line_thickness(img, pixel_of(rs, contact_x(s, 2), 2)),
            t4 = line_thickness(img, pixel_of(rs, contact_x(s, 4), 2));
  CAPTURE(t1);
  CAPTURE(t2);
  CAPTURE(t4);
  CHECK(std::abs(t1 - 0.4 * rs.camera.pixels_per_unit) <= 1.5);
  CHECK(std::abs(t2 - 2 * t1) <= 2);
  CHECK(std::abs(t4 - 4 * t1) <= 3);
  // Flat colours in 2D: F / <F> through the sequential map, saturating at 3.
  const Colormap& cm = Colormap::get("sequential");
  CHECK(img.pixel(pixel_of(rs, contact_x(s, 0), 2)[0], pixel_of(rs, contact_x(s, 0), 2)[1]) == cm.at(1.0 / 3));
  CHECK(img.pixel(pixel_of(rs, contact_x(s, 4), 2)[0], pixel_of(rs, contact_x(s, 4), 2)[1]) == cm.at(1.0));
  // Proportional up to a mean grain diameter.
  v.chain_width = 1.0;
  rs = build_render_scene(sim->model(), sim->state(), v);
  CHECK(rs.segments[0].width == doctest::Approx(1.0));
  CHECK(rs.segments[2].width == doctest::Approx(2.0));
  CHECK(rs.segments[4].width == doctest::Approx(2.0));
}

TEST_CASE("the colour bar shows the chains' force over flat grains, and no margin is kept when nothing needs one") {
  auto sim = test::simulation_from(row_scene());
  sim->prepare();
  View v = test::plain_view(1300, 300, {"grains", "chains", "colorbar"});
  v.color_by = "";  // the scene default: flat grains under chains
  RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(rs.colorbar.on);
  CHECK(rs.colorbar.label == "normal force / mean");
  CHECK(rs.colorbar.lo == 0);
  CHECK(rs.colorbar.hi == 3);
  CHECK(rs.spheres.front().color == Rgba{191, 191, 199, 255});  // flat_color
  Rasterizer raster(1);
  Image img = raster.draw(rs);
  compose_overlays(rs, img);
  // The bar's colour a third of the way up is the colour of the chain at the mean force.
  const ColorBar& b = rs.colorbar;
  const int y_mean = b.y + static_cast<int>(std::lround((b.height - 1) * (1 - 1.0 / 3)));
  const auto mid = pixel_of(rs, contact_x(sim->state(), 0), 2);
  CHECK(test::near(img.pixel(b.x + b.width / 2, y_mean), img.pixel(mid[0], mid[1]), 3));
  // Grains coloured by a quantity: their bar.
  v.color_by = "vx";
  CHECK(build_render_scene(sim->model(), sim->state(), v).colorbar.label.find("vx") == 0);
  // Flat grains without chains: no bar, and the box takes the whole width.
  v = test::plain_view(1300, 300, {"grains", "colorbar"});
  v.color_by = "flat";
  rs = build_render_scene(sim->model(), sim->state(), v);
  CHECK_FALSE(rs.colorbar.on);
  const RenderScene no_bar = build_render_scene(sim->model(), sim->state(), test::plain_view(1300, 300, {"grains"}));
  CHECK(rs.camera.domain_px == no_bar.camera.domain_px);
  CHECK(rs.camera.domain_px[0] + rs.camera.domain_px[2] > 1300 - 25);
}

TEST_CASE("the box outline: a rectangle in 2D following the box lengths, the Lees-Edwards offset marked") {
  auto sim = test::simulation_from(R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [8, 4]
periodic = [true, true]
[shear]
rate = 0.1
[contact]
model = "linear"
k_n = 1000
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[2, 2]]
[run]
dt = 1e-3
)");
  sim->state().box.len = {6, 4, 1};  // as a controlled box would have it
  sim->state().box.le_offset = 1.5;
  View v = test::plain_view(800, 400, {"box"});
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(rs.lines.size() == 5);  // four edges and the offset mark
  Rasterizer raster(1);
  const Image img = raster.draw(rs);
  auto dark = [&](double x, double y) {
    const auto p = pixel_of(rs, x, y);
    const Rgba c = img.pixel(p[0], p[1]);
    return c.r < 100 && c.g < 100 && c.b < 100;
  };
  for (const auto& p : {std::array<double, 2>{3, 0}, {3, 4}, {0, 2}, {6, 2}}) CHECK(dark(p[0], p[1]));
  CHECK_FALSE(dark(3, 2));
  CHECK_FALSE(dark(7.5, 2));  // beyond the box's new length
  CHECK(dark(1.5, 4));        // the offset of the image above
  CHECK(dark(1.5, 4.08));
  CHECK_FALSE(dark(3, 4.08));
}

TEST_CASE("the box outline in 3D: twelve edges, hidden behind an opaque grain and drawn in front of it") {
  auto sim = test::simulation_from(R"(
[scene]
dimension = 3
[domain]
lo = [0, 0, 0]
hi = [4, 4, 4]
[contact]
model = "hooke"
k_n = 1000
[[grains]]
radius = 1.9
placement = "explicit"
positions = [[2, 2, 2]]
[run]
dt = 1e-3
)");
  View v = test::plain_view(500, 500, {"box", "grains"});
  v.color_by = "flat";
  v.flat_color[0] = 1;
  v.flat_color[1] = v.flat_color[2] = 0.2;
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(rs.lines.size() == 12);
  Rasterizer raster(1);
  const Image img = raster.draw(rs);
  const auto c = project(rs.camera, {2, 2, 2}, rs.width, rs.height);
  const auto rim = project(rs.camera, {2, 2, 2 + 1.9}, rs.width, rs.height);
  const double r_px = std::hypot(rim[0] - c[0], rim[1] - c[1]);
  int hidden = 0, shown = 0;
  for (int c0 = 0; c0 < 8; ++c0)
    for (int k = 0; k < 3; ++k) {
      if ((c0 >> k) & 1) continue;
      for (double f = 0.1; f < 0.95; f += 0.1) {
        std::array<double, 3> x{};
        for (int a = 0; a < 3; ++a) x[a] = 4.0 * ((c0 >> a) & 1) + (a == k ? 4.0 * f : 0.0);
        const auto p = project(rs.camera, x, rs.width, rs.height);
        const double off = std::hypot(p[0] - c[0], p[1] - c[1]);
        if (std::abs(off - r_px) < 6) continue;  // the silhouette
        const Rgba px = img.pixel(static_cast<int>(p[0]), static_cast<int>(p[1]));
        const bool ink = px.r < 80 && px.g < 80 && px.b<80, red = px.r> 90 && px.r > px.g + 40;
        CAPTURE(x[0]);
        CAPTURE(x[1]);
        CAPTURE(x[2]);
        if (off > r_px) {
          CHECK(ink);  // nothing in front of it
        } else if (p[2] > c[2]) {
          CHECK(red);  // behind the grain
          ++hidden;
        } else {
          CHECK(ink);  // in front of the grain
          ++shown;
        }
      }
    }
  CHECK(hidden > 3);
  CHECK(shown > 3);
}
