// The renderer, checked by pixel facts rather than "a file was written".
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>

#include "render/render_support.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::render;
using silt::test::kRow;
using silt::test::pixel_of;
using silt::test::white;

namespace {

// Number of non-white pixels in the column through (x, y), within `reach` pixels of it.
int thickness(const Image& img, std::array<int, 2> at, int reach) {
  int n = 0;
  for (int dy = -reach; dy <= reach; ++dy) n += !white(img.pixel(at[0], at[1] + dy));
  return n;
}

View plain(int w, int h, std::vector<std::string> draw) { return test::plain_view(w, h, std::move(draw)); }

}  // namespace

TEST_CASE("a force chain colours the pixels along the segment and nowhere else, and more force draws a wider line") {
  auto sim = test::simulation_from(kRow);
  sim->prepare();
  View v = plain(800, 400, {"chains"});
  v.chain_width = 0.4;
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(rs.segments.size() == 2);
  Rasterizer raster(1);
  const Image img = raster.draw(rs);
  // Along each segment: coloured. Above and below the row, and outside the chain: white.
  const auto left = pixel_of(rs, 2.48, 2.0), right = pixel_of(rs, 4.455, 2.0);
  CHECK_FALSE(white(img.pixel(left[0], left[1])));
  CHECK_FALSE(white(img.pixel(right[0], right[1])));
  for (double y : {0.5, 1.2, 2.8, 3.5}) {
    const auto p = pixel_of(rs, 2.48, y);
    CHECK(white(img.pixel(p[0], p[1])));
  }
  const auto out = pixel_of(rs, 7.5, 2.0);
  CHECK(white(img.pixel(out[0], out[1])));
  // The left contact carries 4 times the force of the right one: a wider line.
  const int tl = thickness(img, left, 60), tr = thickness(img, right, 60);
  CHECK(tr > 0);
  CHECK(tl > 2 * tr);
}

TEST_CASE("a known vorticity field: positive red, negative blue, zero white") {
  auto sim = test::simulation_from(kRow);
  GridField g;
  g.name = "vorticity";
  g.nx = 8;
  g.ny = 4;
  g.h = {1, 1, 1};
  g.value.assign(32, 0.0);
  for (int j = 0; j < 4; ++j) {
    g.value[j * 8 + 0] = g.value[j * 8 + 1] = 1.0;   // x in [0, 2): positive
    g.value[j * 8 + 6] = g.value[j * 8 + 7] = -1.0;  // x in [6, 8): negative
  }
  View v = plain(800, 400, {"field"});
  v.field_range_auto = false;
  v.field_range[0] = -1;
  v.field_range[1] = 1;
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v, &g);
  Rasterizer raster(1);
  const Image img = raster.draw(rs);
  const Rgba pos = img.pixel(pixel_of(rs, 1.0, 2.0)[0], pixel_of(rs, 1.0, 2.0)[1]);
  const Rgba neg = img.pixel(pixel_of(rs, 7.0, 2.0)[0], pixel_of(rs, 7.0, 2.0)[1]);
  const Rgba zero = img.pixel(pixel_of(rs, 4.0, 2.0)[0], pixel_of(rs, 4.0, 2.0)[1]);
  CHECK(pos.r > 120);
  CHECK(pos.r > pos.b + 60);
  CHECK(neg.b > neg.r + 60);
  CHECK(zero.r > 235);
  CHECK(zero.g > 235);
  CHECK(zero.b > 235);
  CHECK(pos == Colormap::get("diverging").at(1.0));
  CHECK(neg == Colormap::get("diverging").at(0.0));
}

TEST_CASE("Lamb-Oseen and Taylor-Green vortices put the expected colours at known points") {
  auto sim = test::simulation_from(kRow);
  View v = plain(800, 400, {"field"});
  const GridField lo = lamb_oseen_vorticity(256, 128, {0, 0}, {8, 4}, {4, 2}, 1.0, 0.5);
  RenderScene rs = build_render_scene(sim->model(), sim->state(), v, &lo);
  Rasterizer raster(1);
  Image img = raster.draw(rs);
  const auto c = pixel_of(rs, 4.0, 2.0), far = pixel_of(rs, 7.5, 3.5);
  CHECK(img.pixel(c[0], c[1]).r > img.pixel(c[0], c[1]).b + 60);  // the core: strongest positive
  CHECK(white(img.pixel(far[0], far[1])));                        // exp(-r^2/rc^2) ~ 0 far away
  // Taylor-Green on [0, 4]^2: omega > 0 at (1, 1), < 0 at (3, 1), 0 on the cell edges.
  const GridField tg = taylor_green_vorticity(128, 128, 4.0, 1.0);
  rs = build_render_scene(sim->model(), sim->state(), v, &tg);
  img = raster.draw(rs);
  const auto a = pixel_of(rs, 1.0, 1.0), b = pixel_of(rs, 3.0, 1.0), e = pixel_of(rs, 2.0, 1.0);
  CHECK(img.pixel(a[0], a[1]).r > img.pixel(a[0], a[1]).b + 60);
  CHECK(img.pixel(b[0], b[1]).b > img.pixel(b[0], b[1]).r + 60);
  CHECK(img.pixel(e[0], e[1]).g > 200);  // near zero: near white
}

TEST_CASE("an automatic grain range: white at 0 on the diverging map, and one value in the middle") {
  auto sim = test::simulation_from(kRow);
  View v = plain(800, 400, {"grains", "colorbar"});
  v.color_by = "vx";
  const auto range = [&](const std::string& map, std::vector<double> vx) {
    for (int i = 0; i < 3; ++i) sim->state().particle_v[2 * i] = vx[i];
    v.colormap = map;
    const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
    return std::array<double, 2>{rs.colorbar.lo, rs.colorbar.hi};
  };
  CHECK(range("sequential", {-0.1, 0.05, 0.2}) == std::array<double, 2>{-0.1, 0.2});
  CHECK(range("diverging", {-0.1, 0.05, 0.2}) == std::array<double, 2>{-0.2, 0.2});  // (white at 0.05 before)
  // Every grain falling at one speed: painted the middle of the map (it was its deep end).
  CHECK(range("sequential", {-0.004, -0.004, -0.004}) == std::array<double, 2>{-0.008, 0.0});
  CHECK(range("diverging", {0, 0, 0}) == std::array<double, 2>{-1, 1});
  v.color_by = "speed";
  CHECK(range("sequential", {0, 0, 0}) == std::array<double, 2>{0, 1});  // at rest: the low end
}

TEST_CASE("the colour bar spans the stated range, with its labels") {
  auto sim = test::simulation_from(kRow);
  View v = plain(800, 400, {"grains", "colorbar"});
  v.color_by = "vx";
  v.range_auto = false;
  v.range[0] = 2;
  v.range[1] = 5;
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(rs.colorbar.on);
  CHECK(rs.colorbar.lo == 2);
  CHECK(rs.colorbar.hi == 5);
  Rasterizer raster(1);
  Image img = raster.draw(rs);
  compose_overlays(rs, img);
  const ColorBar& b = rs.colorbar;
  const Colormap& cm = Colormap::get("sequential");
  CHECK(img.pixel(b.x + b.width / 2, b.y) == cm.at(1.0));
  CHECK(img.pixel(b.x + b.width / 2, b.y + b.height - 1) == cm.at(0.0));
  const int mid = b.height / 2;
  CHECK(img.pixel(b.x + b.width / 2, b.y + mid) == cm.at(1.0 - static_cast<double>(mid) / (b.height - 1)));
  // Labels: dark text pixels right of the bar's top and bottom.
  auto ink_near = [&](int x0, int y0) {
    int n = 0;
    for (int y = y0 - 12; y <= y0 + 2; ++y)
      for (int x = x0; x < x0 + 30; ++x) n += img.pixel(x, y).r < 128;
    return n;
  };
  CHECK(ink_near(b.x + b.width + 5, b.y + 6) > 5);
  CHECK(ink_near(b.x + b.width + 5, b.y + b.height + 4) > 5);
  // The grains take the colours of their values: vx = 0 is below the range, the lowest colour.
  const auto g0 = pixel_of(rs, 1.5, 2.0);
  const Rgba c0 = img.pixel(g0[0], g0[1]);
  CHECK(std::abs(static_cast<int>(c0.b) - static_cast<int>(cm.at(0.0).b)) < 90);
}

TEST_CASE("depth is right for overlapping spheres whatever the drawing order") {
  const char* two = R"(
[scene]
dimension = 3
[domain]
lo = [-5, -5, -5]
hi = [5, 5, 5]
[contact]
model = "hooke"
k_n = 1000
[[grains]]
radius = 1.0
placement = "explicit"
positions = [[0, 0, 0], [0, 0, 2.5]]
[run]
dt = 1e-3
)";
  auto sim = test::simulation_from(two);
  View v = plain(400, 400, {"grains"});
  v.color_by = "id";
  v.colormap = "diverging";
  v.range_auto = false;
  v.range[0] = 0;
  v.range[1] = 1;
  v.elevation = 89;  // looking down z: grain 1 (z = 2.5) is in front of grain 0
  v.target_auto = false;
  v.target[0] = v.target[1] = v.target[2] = 0;
  v.distance = 20;
  RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  Rasterizer raster(1);
  const auto centre = pixel_of(rs, 0, 0, 2.5);
  const Rgba front = raster.draw(rs).pixel(centre[0], centre[1]);
  CHECK(front.r > front.b + 60);            // id 1: red end
  std::swap(rs.spheres[0], rs.spheres[1]);  // other drawing order, same picture
  CHECK(raster.draw(rs).pixel(centre[0], centre[1]) == front);
  // From below, grain 0 (blue) is in front.
  v.elevation = -89;
  rs = build_render_scene(sim->model(), sim->state(), v);
  const auto c2 = pixel_of(rs, 0, 0, 0);
  const Rgba back = raster.draw(rs).pixel(c2[0], c2[1]);
  CHECK(back.b > back.r + 60);
}

TEST_CASE("PNG: written atomically, decodes with the expected size and channels") {
  auto sim = test::simulation_from(kRow);
  Rasterizer raster(1);
  const Image img = render_frame(raster, sim->model(), sim->state(), plain(321, 123, {"grains", "time", "scalebar"}));
  write_png("render_test.png", img);
  const Image back = read_png("render_test.png");
  CHECK(back.width == 321);
  CHECK(back.height == 123);
  CHECK(back.rgba.size() == 321u * 123u * 4u);
  CHECK(back.rgba == img.rgba);
  std::remove("render_test.png");
  CHECK_THROWS_AS(write_png("no_dir/x.png", img), IoError);
  CHECK_THROWS_AS(read_png("no_such.png"), IoError);
}

TEST_CASE("bad input: sizes, colormaps, NaN fields and empty frames give messages, not crashes") {
  auto sim = test::simulation_from(kRow);
  View v = plain(0, 100, {"grains"});
  CHECK_THROWS_WITH_AS(build_render_scene(sim->model(), sim->state(), v), doctest::Contains("outside 16 .. 16384"),
                       RenderError);
  v = plain(100000, 100, {"grains"});
  CHECK_THROWS_AS(build_render_scene(sim->model(), sim->state(), v), RenderError);
  // At most 64 Mpx (16384 x 16384 would take 4.3 GB).
  v = plain(16384, 16384, {"grains"});
  CHECK_THROWS_WITH_AS(build_render_scene(sim->model(), sim->state(), v),
                       doctest::Contains("above the limit of 64 Mpx"), RenderError);
  CHECK_THROWS_AS(build_render_scene(sim->model(), sim->state(), plain(8193, 8192, {})), RenderError);
  CHECK(build_render_scene(sim->model(), sim->state(), plain(8192, 8192, {})).width == 8192);
  CHECK(build_render_scene(sim->model(), sim->state(), plain(16384, 64, {})).width == 16384);
  v = plain(200, 100, {"grains"});
  v.colormap = "jet";
  CHECK_THROWS_WITH_AS(build_render_scene(sim->model(), sim->state(), v), doctest::Contains("unknown colormap 'jet'"),
                       RenderError);
  // NaN in a field: drawn grey, with a warning.
  GridField g;
  g.name = "vorticity";
  g.nx = 2;
  g.ny = 1;
  g.h = {4, 4, 1};
  g.value = {std::nan(""), 1.0};
  v = plain(200, 100, {"field"});
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v, &g);
  REQUIRE(rs.warnings.size() == 1);
  CHECK(rs.warnings[0].find("NaN") != std::string::npos);
  Rasterizer raster(1);
  const Image img = raster.draw(rs);
  const auto p = pixel_of(rs, 2.0, 2.0);
  CHECK(img.pixel(p[0], p[1]) == Rgba{128, 128, 128, 255});
  // Nothing to draw: the background.
  v = plain(64, 32, {});
  const Image empty = raster.draw(build_render_scene(sim->model(), sim->state(), v));
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) REQUIRE(white(empty.pixel(x, y)));
  // A field asked for where there is none: a warning, no crash.
  v = plain(64, 32, {"field"});
  CHECK(build_render_scene(sim->model(), sim->state(), v).warnings.size() == 1);
}

TEST_CASE("a frame above 64 Mpx is a scene error at render.width, with its file:line:col") {
  const std::string big = std::string(kRow) + "[render]\nwidth = 16384\nheight = 16384\n";
  const std::string e = test::scene_error(big);
  CHECK(e.find("bad.toml:17:9: ") == 0);
  CHECK(e.find("render.width x render.height = 16384 x 16384") != std::string::npos);
  CHECK(e.find("limit of 64 Mpx") != std::string::npos);
  CHECK(test::scene_error(std::string(kRow) + "[render]\nwidth = 8192\nheight = 8192\n").empty());
  CHECK(test::scene_error(std::string(kRow) + "[render]\nheight = 8193\nwidth = 8192\n").find("bad.toml:18:9: ") == 0);
}

TEST_CASE("colour ranges whose span overflows and zero slab normals are refused at their keys") {
  // [-1e308, 1e308]: hi - lo is inf, every value mapped to the low end (a frame of one colour).
  const std::string e = test::scene_error(std::string(test::kRow) + "[render]\nrange = [-1e308, 1e308]\n");
  CHECK(e.find("bad.toml:17:9: the span hi - lo = inf") == 0);
  CHECK(test::scene_error(std::string(test::kRow) + "[render]\nfield_range = [-1e308, 1e308]\n").find("span") !=
        std::string::npos);
  CHECK(test::scene_error(std::string(test::kRow) + "[render]\nrange = [-1e307, 1e307]\n").empty());
  // A fluid field's keys in a scene without a fluid (taken, they changed no pixel), and a profile's
  // component without a profile.
  CHECK(test::scene_error(std::string(test::kRow) + "[render]\nfield = \"pressure\"\n")
            .find("render.field sets how a fluid's field is drawn, and this scene has no fluid") != std::string::npos);
  CHECK_THROWS_WITH_AS(compile(parse_scene(test::kRow, "row.toml", {parse_override("output.profile_component=y")})),
                       doctest::Contains("output.profile_component needs a profile (output.profile_axis)"), SceneError);
  // A zero slab normal put every grain in the slab; a tiny one is a direction.
  const std::string cube = R"([scene]
dimension = 3
[domain]
lo = [0, 0, 0]
hi = [4, 4, 4]
[contact]
model = "hooke"
k_n = 1e5
[[grains]]
count = 4
radius = 0.5
[run]
dt = 1e-4
[render]
)";
  CHECK(test::scene_error(cube + "slab_normal = [0, 0, 0]\n").find("non-zero finite") != std::string::npos);
  const Model m = test::model_from(cube + "slab_normal = [0, 1e-300, 0]\n");
  CHECK(m.render.slab_normal[0] == 0);
  CHECK(m.render.slab_normal[1] == 1);
  CHECK(m.render.slab_normal[2] == 0);
}

TEST_CASE("3D: chains in a slab, a field slice with the grains it cuts") {
  const char* bed = R"(
[scene]
dimension = 3
seed = 4
[domain]
lo = [0, 0, 0]
hi = [6, 6, 6]
periodic = [true, true, true]
[box]
pressure = 1.0
[contact]
model = "linear"
k_n = 1e3
damping = 0.7
[[grains]]
count = 150
radius_min = 0.4
radius_max = 0.5
placement = "random"
[run]
dt_over_tc = 0.05
)";
  auto sim = test::simulation_from(bed, 2);
  for (int k = 0; k < 4000; ++k) REQUIRE(sim->step());
  View v = plain(400, 300, {"chains"});
  const RenderScene all = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(all.segments.size() > 20);
  v.slab_half_width = 0.5;
  v.slab_center_auto = false;
  v.slab_center[0] = v.slab_center[1] = v.slab_center[2] = 3.0 * sim->state().box.len[0] / 6.0;
  const RenderScene slab = build_render_scene(sim->model(), sim->state(), v);
  CHECK(slab.segments.size() < all.segments.size());
  CHECK(slab.segments.size() > 0);
  for (const auto& s : slab.segments) CHECK(std::abs(0.5 * (s.a[1] + s.b[1]) - v.slab_center[1]) <= 0.5 + 1e-6);
  // Translucent flat grains over chains in 3D by default; with a slab, only the grains in it.
  v.draw = {"grains", "chains"};
  v.color_by = "";
  const RenderScene both = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(!both.spheres.empty());
  CHECK(both.spheres.front().color == Rgba{191, 191, 199, 64});
  CHECK(static_cast<int64_t>(both.spheres.size()) < sim->state().n);
  for (const auto& g : both.spheres) CHECK(std::abs(g.centre[1] - v.slab_center[1]) <= 0.5 + 1e-6);
  // Not given, the slab is centred on the box as it is now: this one shrank under the pressure
  // (centred on the scene's box, it sat off the compressed box's middle).
  const Box& box = sim->state().box;
  REQUIRE(box.len[1] < 5.9);
  View centred = plain(400, 300, {"grains", "chains"});
  centred.slab_half_width = 0.5;
  const RenderScene mid = build_render_scene(sim->model(), sim->state(), centred);
  REQUIRE(!mid.spheres.empty());
  for (const auto& g : mid.spheres) CHECK(std::abs(g.centre[1] - (box.lo[1] + 0.5 * box.len[1])) <= 0.5 + 1e-6);
  v.slab_half_width = 0;
  CHECK(static_cast<int64_t>(build_render_scene(sim->model(), sim->state(), v).spheres.size()) == sim->state().n);
  // A slice at z = 3 of a field equal to z: one colour on the plane, and only the grains it cuts.
  GridField g;
  g.name = "vorticity";
  g.nx = g.ny = g.nz = 6;
  g.lo = {0, 0, 0};
  g.h = {1, 1, 1};
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i) g.value.push_back(k + 0.5 - 3.0);  // cell centres z - 3
  v.draw = {"field"};
  v.slice_normal[0] = v.slice_normal[1] = 0;
  v.slice_normal[2] = 1;
  v.slice_position = 3.2;
  v.field_range_auto = false;
  v.field_range[0] = -3;
  v.field_range[1] = 3;
  const RenderScene sl = build_render_scene(sim->model(), sim->state(), v, &g);
  REQUIRE(sl.fields.size() == 1);
  CHECK(sl.fields[0].tex_w == 6);  // one texel per cell along an axis
  // Between the cell centres z = 2.5 (-0.5) and 3.5 (0.5), linearly: 0.2 at z = 3.2.
  CHECK(test::near(sl.fields[0].texels.front(), Colormap::get("diverging").at((0.2 + 3.0) / 6.0), 1));
  for (const auto& c : sl.fields[0].corners) CHECK(c[2] == doctest::Approx(3.2));
  int64_t cut = 0;
  for (int64_t i = 0; i < sim->state().n; ++i)
    cut += std::abs(sim->state().particle_x[3 * i + 2] - 3.2) < sim->state().particle_r[i];
  CHECK(static_cast<int64_t>(sl.spheres.size()) == cut);
  for (const auto& s : sl.spheres) CHECK(s.centre[2] == doctest::Approx(3.2));
}

TEST_CASE("periodic images: a disk across the boundary is drawn on both sides") {
  const char* edge = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [8, 4]
periodic = [true, false]
[contact]
model = "linear"
k_n = 1000
[[grains]]
radius = 1.0
placement = "explicit"
positions = [[0.3, 2]]
[run]
dt = 1e-3
)";
  auto sim = test::simulation_from(edge);
  View v = plain(800, 400, {"grains"});
  v.color_by = "flat";
  Rasterizer raster(1);
  RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  CHECK(rs.spheres.size() == 1);
  const auto right = pixel_of(rs, 7.9, 2.0);
  CHECK(white(raster.draw(rs).pixel(right[0], right[1])));
  v.periodic_images = true;
  rs = build_render_scene(sim->model(), sim->state(), v);
  CHECK(rs.spheres.size() == 2);
  CHECK_FALSE(white(raster.draw(rs).pixel(right[0], right[1])));
}

TEST_CASE("under Lees-Edwards shear the image of a grain across y is shifted by the offset") {
  // A disk of radius 0.5 at (2, 9.8) in a 10 x 10 sheared box with offset 3: it pokes out of the
  // top, and its image below is at (2 - 3 mod 10, 9.8 - 10) = (9, -0.2).
  auto sim = test::simulation_from(R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [10, 10]
periodic = [true, true]
[shear]
rate = 0.1
[contact]
model = "linear"
k_n = 1000
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[2, 9.8]]
[run]
dt = 1e-3
)");
  sim->state().box.le_offset = 3;
  View v = plain(400, 400, {"grains"});
  v.periodic_images = true;
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(rs.spheres.size() == 2);
  CHECK(rs.spheres[1].centre[0] == doctest::Approx(9.0));
  CHECK(rs.spheres[1].centre[1] == doctest::Approx(-0.2));
}

// A failed run's state (NaN box lengths and positions) drawn by a frame hook: the frame is drawn
// whole, with no value converted from a NaN (UBSan found frame_2d converting the 2D box's pixel
// extent, from a shell session whose sheared run blew up).
TEST_CASE("a frame of a failed state (NaN box and positions) is drawn without converting a NaN") {
  const std::string block3d =
      "[scene]\ndimension = 3\n[domain]\nlo = [-1, -1, -1]\nhi = [3, 3, 3]\n[contact]\nmodel = \"hooke\"\n"
      "k_n = 1000\n[[grains]]\nradius = 0.49\nplacement = \"lattice\"\nlattice = \"sc\"\nspacing = 1.0\n"
      "region_lo = [0, 0, 0]\nregion_hi = [2, 2, 2]\n[run]\ndt = 1e-3\n";
  for (const std::string& scene : {std::string(kRow), block3d}) {
    auto sim = test::simulation_from(scene);
    State s = sim->state();
    const double nan = std::nan("");
    s.box.len = {nan, nan, nan};
    for (double& x : s.particle_x) x = nan;
    const View v = plain(160, 120, {"grains", "chains", "box", "time", "scalebar"});
    const RenderScene rs = build_render_scene(sim->model(), s, v);
    for (int d : rs.camera.domain_px) CHECK(std::abs(d) <= 1000);
    Rasterizer raster(1);
    const Image img = raster.draw(rs);
    CHECK(img.width == 160);
    CHECK(img.height == 120);
  }
}

// A frame too short for its overlays' margins: the room left for the domain was negative, so was
// the scale, and the grains were drawn half a turn round (the left one on the right).
TEST_CASE("a frame too small for its overlays draws the grains where they are, the margins dropped") {
  auto sim = test::simulation_from(kRow);
  const View v = plain(400, 30, {"grains", "time", "scalebar"});
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  CHECK(rs.camera.pixels_per_unit > 0);
  const auto left = test::pixel_of(rs, 1.5, 2), right = test::pixel_of(rs, 5.45, 2);
  CHECK(left[0] < right[0]);
  CHECK(left[0] >= 0);
  CHECK(right[0] < 400);
}

// No grain to colour (all frozen): the colour bar's range read 1e308 to 1e308.
TEST_CASE("a colour bar with no grain to colour keeps a finite range") {
  auto sim = test::simulation_from(std::string(kRow) + "");
  State s = sim->state();
  for (auto& f : s.particle_frozen) f = 1;
  View v = plain(400, 200, {"grains", "colorbar"});
  v.color_by = "height";
  const RenderScene rs = build_render_scene(sim->model(), s, v);
  REQUIRE(rs.colorbar.on);
  CHECK(std::abs(rs.colorbar.lo) < 1e300);
  CHECK(std::abs(rs.colorbar.hi) < 1e300);
  CHECK(rs.colorbar.hi > rs.colorbar.lo);
}
