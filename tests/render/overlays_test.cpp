// Overlays (scale bar, time and step) and the automatic framing of 3D domains.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>

#include "render/render_support.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::render;
using silt::test::kRow;
using silt::test::pixel_of;

namespace {

// A chute-like domain: 40 x 20 x 30, periodic in x and y, gravity along -z, grains in a bed of
// the lower `bed` of z.
std::string chute_like(double bed) {
  return test::fill(R"(
[scene]
dimension = 3
[domain]
lo = [0, 0, 0]
hi = [40, 20, 30]
periodic = [true, true, false]
[gravity]
magnitude = 1.0
[contact]
model = "hooke"
k_n = 1000
[[grains]]
radius = 0.45
placement = "lattice"
lattice = "sc"
spacing = 2.0
region_lo = [0, 0, 0.5]
region_hi = [40, 20, {bed}]
[run]
dt = 1e-3
)",
                    {{"bed", bed}});
}

// The number in front of " m" in a scale bar label.
double label_length(const std::string& label) { return std::strtod(label.c_str(), nullptr); }

// Pixels of the box's corners, and the bounding rectangle they span.
struct Corners {
  bool inside = true;
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
};
Corners project_corners(const RenderScene& rs, const Box& b) {
  Corners c;
  for (int k = 0; k < 8; ++k) {
    const auto p = project(
        rs.camera,
        {b.lo[0] + (k & 1) * b.len[0], b.lo[1] + ((k >> 1) & 1) * b.len[1], b.lo[2] + ((k >> 2) & 1) * b.len[2]},
        rs.width, rs.height);
    c.inside = c.inside && p[0] >= 0 && p[0] < rs.width && p[1] >= 0 && p[1] < rs.height && p[2] > 0;
    c.x0 = std::min(c.x0, p[0]);
    c.x1 = std::max(c.x1, p[0]);
    c.y0 = std::min(c.y0, p[1]);
    c.y1 = std::max(c.y1, p[1]);
  }
  return c;
}

}  // namespace

TEST_CASE("the scale bar's length in pixels is its label's length in world units (2D)") {
  auto sim = test::simulation_from(kRow);
  const View v = test::plain_view(800, 400, {"grains", "scalebar"});
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(rs.scalebar.on);
  const double len = label_length(rs.scalebar.label);
  CHECK(len == 1.0);  // a fifth of the 8 m box, rounded down to 1, 2 or 5 times a power of ten
  Rasterizer raster(1);
  Image img = raster.draw(rs);
  compose_overlays(rs, img);
  // The drawn bar: the dark run along its middle row.
  const int row = rs.scalebar.y + 2;
  int x = rs.scalebar.x, drawn = 0;
  while (x < img.width && img.pixel(x, row).r < 100) ++drawn, ++x;
  const double world = std::abs(pixel_of(rs, len, 2)[0] - pixel_of(rs, 0, 2)[0]);
  CHECK(std::abs(drawn - world) <= 1);
  CHECK(drawn > 50);
}

// A 2D box the frame cannot hold (here its height is negative: framed as the unit square) keeps
// its length: a fifth of it was the bar's length in the frame's scale, 6.8e8 pixels here. And the
// overlays filled a bar pixel by pixel out to its end, inside the image or not: the terminal fuzz
// target's slowest input (2026-11-28, 25 s; 65 s replayed alone) spent its time there.
TEST_CASE("the scale bar of a box the frame cannot hold is a sixth of the frame, and any bar draws promptly") {
  auto sim = test::simulation_from(kRow);
  State s = sim->state();
  s.box.len[0] = 1e7;
  s.box.len[1] = -1;
  const View v = test::plain_view(800, 400, {"grains", "scalebar"});
  RenderScene rs = build_render_scene(sim->model(), s, v);
  REQUIRE(rs.scalebar.on);
  CHECK(rs.scalebar.width_px > 0);
  CHECK(rs.scalebar.width_px <= v.width / 6);
  CHECK(label_length(rs.scalebar.label) * rs.camera.pixels_per_unit ==
        doctest::Approx(rs.scalebar.width_px).epsilon(0.01));
  // The overlays clip what they fill to the image: a bar two billion pixels long costs what one
  // across the image does.
  rs.scalebar.width_px = 2'000'000'000;
  Rasterizer raster(1);
  Image img = raster.draw(rs);
  const auto start = std::chrono::steady_clock::now();
  compose_overlays(rs, img);
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 2.0);
  CHECK(img.pixel(v.width - 1, rs.scalebar.y + 2).r < 100);  // drawn to the image's edge
}

TEST_CASE("the time and step are drawn, and another time draws other pixels") {
  auto sim = test::simulation_from(kRow);
  Rasterizer raster(1);
  auto frame = [&](std::vector<std::string> draw) {
    return render_frame(raster, sim->model(), sim->state(), test::plain_view(400, 200, std::move(draw)));
  };
  // The text's region: the top left, above the box.
  auto region_differs = [](const Image& a, const Image& b) {
    int n = 0;
    for (int y = 0; y < 36; ++y)
      for (int x = 0; x < 300; ++x) n += !(a.pixel(x, y) == b.pixel(x, y));
    return n;
  };
  const Image none = frame({"grains"});
  const Image t0 = frame({"grains", "time"});
  CHECK(region_differs(none, t0) > 100);
  sim->state().t = 0.125;
  sim->state().step = 125;
  const Image t1 = frame({"grains", "time"});
  CHECK(region_differs(t0, t1) > 20);
  CHECK(region_differs(t1, frame({"grains", "time"})) == 0);  // the same time, the same pixels
}

TEST_CASE("a frame too narrow for the time and the step on one line has them on two, whole") {
  // (the step was cut off at the frame's edge)
  auto sim = test::simulation_from(kRow);
  sim->state().t = 0.125;
  sim->state().step = 123456;
  auto texts = [&](int width) {
    return build_render_scene(sim->model(), sim->state(), test::plain_view(width, 200, {"grains", "time"})).texts;
  };
  const auto wide = texts(400);
  REQUIRE(wide.size() == 1);
  CHECK(wide[0].text == "t = 0.125 s    step 123456");
  const auto narrow = texts(160);
  REQUIRE(narrow.size() == 2);
  CHECK(narrow[0].text == "t = 0.125 s");
  CHECK(narrow[1].text == "step 123456");
  CHECK(narrow[1].y > narrow[0].y);
  for (const TextItem& t : narrow) CHECK(t.x + text_width(t.text, t.size) <= 160);
}

TEST_CASE("in 3D the scale bar measures lengths at the target's depth") {
  auto sim = test::simulation_from(chute_like(10));
  View v = test::plain_view(900, 600, {"grains", "scalebar"});
  for (double az : {30.0, 120.0}) {
    v.azimuth = az;
    const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
    REQUIRE(rs.scalebar.on);
    CHECK(rs.scalebar.label.find(" m at the target") != std::string::npos);
    const double len = label_length(rs.scalebar.label);
    // A segment of that length through the target, across the screen (the camera's x axis).
    const auto& t = rs.camera.target;
    const std::array<double, 3> right{rs.camera.view[0], rs.camera.view[4], rs.camera.view[8]};
    std::array<double, 3> a{}, b{};
    for (int k = 0; k < 3; ++k) {
      a[k] = t[k] - 0.5 * len * right[k];
      b[k] = t[k] + 0.5 * len * right[k];
    }
    const auto pa = project(rs.camera, a, rs.width, rs.height), pb = project(rs.camera, b, rs.width, rs.height);
    CHECK(std::hypot(pb[0] - pa[0], pb[1] - pa[1]) == doctest::Approx(rs.scalebar.width_px).epsilon(0.01));
  }
}

TEST_CASE("a 3D domain framed automatically: its 8 corners inside the image, filling it") {
  auto sim = test::simulation_from(chute_like(28));
  for (double el : {10.0, 25.0, 60.0, 89.0})
    for (double az : {0.0, 30.0, 90.0, 200.0}) {
      View v = test::plain_view(1280, 720, {"grains", "box", "colorbar", "time", "scalebar"});
      v.color_by = "height";
      v.elevation = el;
      v.azimuth = az;
      const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
      CAPTURE(el);
      CAPTURE(az);
      const Corners c = project_corners(rs, sim->state().box);
      CHECK(c.inside);
      CHECK(c.x1 < rs.colorbar.x - 10);  // left of the colour bar
      CHECK(c.y0 > 36);                  // below the time
      // The limiting direction fills 90 % of the free area (1280 - 130 by 720 - 76 pixels).
      CHECK(std::max((c.x1 - c.x0) / 1150.0, (c.y1 - c.y0) / 644.0) > 0.9);
    }
}

TEST_CASE("the empty top of a tall domain is left out of the frame, but not with the box outline drawn") {
  auto sim = test::simulation_from(chute_like(10));
  View v = test::plain_view(1280, 720, {"grains"});
  RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  const State& s = sim->state();
  double z1 = -1e9;
  for (int64_t i = 0; i < s.n; ++i) z1 = std::max(z1, s.particle_x[3 * i + 2] + s.particle_r[i]);
  REQUIRE(z1 < 10);
  // The camera aims at the middle of the domain below the bed's top, and that fills the frame.
  CHECK(rs.camera.target[2] == doctest::Approx(0.5 * z1));
  Box bed = s.box;
  bed.len[2] = z1;
  const Corners c = project_corners(rs, bed);
  CHECK(c.inside);
  CHECK(std::max((c.x1 - c.x0) / 1240.0, (c.y1 - c.y0) / 680.0) > 0.9);
  v.draw = {"grains", "box"};
  rs = build_render_scene(sim->model(), sim->state(), v);
  CHECK(rs.camera.target[2] == doctest::Approx(15));
  CHECK(project_corners(rs, sim->state().box).inside);
}

TEST_CASE("a frame too narrow for the colour bar's margin has none, and says so") {
  // Below 210 px the margin of 110 px was given up for the domain and the bar was drawn over the
  // grains at width - 90.
  auto sim = test::simulation_from(test::kRow);
  for (int width : {120, 209, 210, 400}) {
    CAPTURE(width);
    View v = test::plain_view(width, 200, {"grains", "colorbar"});
    v.color_by = "speed";
    const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
    const bool room = width >= 210;
    CHECK(rs.colorbar.on == room);
    CHECK(rs.warnings.size() == (room ? 0U : 1U));
    if (room) CHECK(rs.camera.domain_px[0] + rs.camera.domain_px[2] <= rs.colorbar.x);
    else CHECK(rs.warnings[0] == "a frame " + std::to_string(width) + " px wide has no colour bar (it needs 210 px)");
  }
}
