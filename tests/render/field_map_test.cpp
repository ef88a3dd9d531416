// Fields drawn as maps and 3D slices: known colours at known points of analytic fields.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "render/render_support.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::render;
using silt::test::near;
using silt::test::pixel_at;

namespace {

// A 4 x 4 x 4 box with two grains: one cut by the plane z = 2, one above it.
const char* kCube = R"(
[scene]
dimension = 3
[domain]
lo = [0, 0, 0]
hi = [4, 4, 4]
[contact]
model = "hooke"
k_n = 1000
[[grains]]
radius = 0.4
placement = "explicit"
positions = [[1.0303, 3.0, 2.1], [3.0, 3.0, 3.0]]
[run]
dt = 1e-3
)";

// Looking straight down z at the whole box.
View top_view(std::vector<std::string> draw) {
  View v = test::plain_view(600, 600, std::move(draw));
  v.color_by = "flat";
  v.elevation = 89.9;
  v.azimuth = -90;
  return v;
}

}  // namespace

TEST_CASE("field_component: a component or the magnitude of a vector field, a scalar as it is") {
  const GridField w = taylor_green_vorticity_3d(5, 1.0, 1.0);
  CHECK(w.components == 3);
  const GridField z = field_component(w, "z"), m = field_component(w, "magnitude");
  CHECK(z.name == "vorticity_z");
  CHECK(m.name == "|vorticity|");
  REQUIRE(z.value.size() == 125);
  CHECK(z.at(1, 2, 3) == w.at(1, 2, 3, 2));
  const double* c = &w.value[3 * w.cell(1, 2, 3)];
  CHECK(m.at(1, 2, 3) == doctest::Approx(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2])));
  CHECK(field_component(z, "magnitude").value == z.value);
  CHECK_THROWS_AS(field_component(w, "w"), RenderError);
  // The analytic curl: omega_z = 2 u0 k sin(kx) sin(ky) cos(kz) at the cell centres.
  const double k = 2 * std::numbers::pi, x = 1.5 / 5, y = 2.5 / 5, zc = 3.5 / 5;
  CHECK(z.at(1, 2, 3) == doctest::Approx(2 * k * std::sin(k * x) * std::sin(k * y) * std::cos(k * zc)));
  CHECK(w.at(1, 2, 3, 0) == doctest::Approx(-k * std::cos(k * x) * std::sin(k * y) * std::sin(k * zc)));
}

TEST_CASE("3D slice of the Taylor-Green vortex: a vorticity component, its magnitude, the grains the plane cuts") {
  // 33 cells a side: the plane z = L/2 = 2 and the line x = 2 run through cell centres, where
  // cos(kz) = -1 and sin(kx) = 0 exactly.
  auto sim = test::simulation_from(kCube);
  const GridField w = taylor_green_vorticity_3d(33, 4.0, 1.0);  // k = pi / 2, 2 u0 k = pi
  const double h = 4.0 / 33;
  auto centre = [&](int i) { return (i + 0.5) * h; };
  View v = top_view({"field", "colorbar"});
  v.slice_position = 2.0;
  v.slice_component = "z";
  v.field_range_auto = false;
  v.field_range[0] = -std::numbers::pi;
  v.field_range[1] = std::numbers::pi;
  RenderScene rs = build_render_scene(sim->model(), sim->state(), v, &w);
  REQUIRE(rs.fields.size() == 1);
  CHECK(rs.colorbar.label == "vorticity_z");
  CHECK(rs.colorbar.colormap == "diverging");
  Rasterizer raster(1);
  Image img = raster.draw(rs);
  const Colormap& div = Colormap::get("diverging");
  // omega_z = -pi sin(kx) sin(ky) on the plane: negative (blue) at (1, 1), positive (red) at
  // (3, 1), zero (white) on x = 2.
  const Rgba neg = pixel_at(img, rs, centre(8), centre(8), 2.0), pos = pixel_at(img, rs, centre(24), centre(8), 2.0),
             zero = pixel_at(img, rs, centre(16), centre(8), 2.0);
  CHECK(neg.b > neg.r + 60);
  CHECK(pos.r > pos.b + 60);
  CHECK(zero.r > 240);
  CHECK(zero.g > 240);
  CHECK(zero.b > 240);
  CHECK(near(neg, div.at((w.at(8, 8, 16, 2) + std::numbers::pi) / (2 * std::numbers::pi)), 2));
  CHECK(near(pos, div.at((w.at(24, 8, 16, 2) + std::numbers::pi) / (2 * std::numbers::pi)), 2));
  CHECK(near(zero, div.at(0.5), 2));
  // Grains: the one the plane cuts is drawn over the field (flat grey, not the red of omega_z
  // at y = 3), the other is not drawn (the field shows at its place).
  const Rgba cut = pixel_at(img, rs, 1.0303, 3.0, 2.0), above = pixel_at(img, rs, centre(24), centre(24), 2.0);
  CHECK(std::abs(cut.r - cut.b) < 30);
  CHECK(cut.r < 235);
  CHECK(near(above, div.at((w.at(24, 24, 16, 2) + std::numbers::pi) / (2 * std::numbers::pi)), 2));
  CHECK(rs.spheres.size() == 1);

  // The magnitude: the sequential map from 0 to the field's largest value, which (1, 1, 2) holds.
  v.slice_component = "magnitude";
  v.field_range_auto = true;
  rs = build_render_scene(sim->model(), sim->state(), v, &w);
  CHECK(rs.colorbar.colormap == "sequential");
  CHECK(rs.colorbar.lo == 0);
  CHECK(rs.colorbar.hi == doctest::Approx(std::abs(w.at(8, 8, 16, 2))));
  img = raster.draw(rs);
  const Colormap& seq = Colormap::get("sequential");
  CHECK(near(pixel_at(img, rs, centre(8), centre(8), 2.0), seq.at(1.0), 2));
  CHECK(near(pixel_at(img, rs, centre(16), centre(8), 2.0), seq.at(0.0), 2));
}

TEST_CASE("an oblique slice samples the field on its plane, and nothing off the grid") {
  auto sim = test::simulation_from(kCube);
  const GridField w = taylor_green_vorticity_3d(33, 4.0, 1.0);
  View v = top_view({"field"});
  const double s3 = std::sqrt(3.0);
  v.slice_normal[0] = v.slice_normal[1] = v.slice_normal[2] = 1 / s3;
  v.slice_position = 6 / s3;  // x + y + z = 6: through the centre, a hexagon in the cube
  v.slice_component = "z";
  v.field_range_auto = false;
  v.field_range[0] = -std::numbers::pi;
  v.field_range[1] = std::numbers::pi;
  v.distance = 30;  // far enough to see the whole quad
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v, &w);
  REQUIRE(rs.fields.size() == 1);
  for (const auto& c : rs.fields[0].corners) CHECK(c[0] + c[1] + c[2] == doctest::Approx(6.0).epsilon(1e-5));
  Rasterizer raster(1);
  const Image img = raster.draw(rs);
  // On the plane at (1.2, 1.3, 3.5) and (2.9, 0.6, 2.5): the analytic omega_z, within the
  // interpolation error of the grid (h = 0.12: a few colour levels).
  const double k = std::numbers::pi / 2;
  for (const auto& p : {std::array<double, 3>{1.2, 1.3, 3.5}, std::array<double, 3>{2.9, 0.6, 2.5}}) {
    const double omega = std::numbers::pi * std::sin(k * p[0]) * std::sin(k * p[1]) * std::cos(k * p[2]);
    CAPTURE(omega);
    CHECK(near(pixel_at(img, rs, p[0], p[1], p[2]),
               Colormap::get("diverging").at((omega + std::numbers::pi) / (2 * std::numbers::pi)), 8));
  }
  // The quad's corner lies off the cube: background there.
  const auto& c0 = rs.fields[0].corners[0];
  const auto& c2 = rs.fields[0].corners[2];
  double x[3];
  for (int a = 0; a < 3; ++a) x[a] = c0[a] + 0.03 * (c2[a] - c0[a]);
  CHECK((x[0] < 0 || x[1] < 0 || x[2] < 0 || x[0] > 4 || x[1] > 4 || x[2] > 4));
  const auto off = test::pixel_of(rs, x[0], x[1], x[2]);
  REQUIRE((off[0] >= 0 && off[0] < rs.width && off[1] >= 0 && off[1] < rs.height));
  CHECK(test::white(img.pixel(off[0], off[1])));
  // A plane that misses the grid: a warning, no quad.
  v.slice_position = 100;
  const RenderScene miss = build_render_scene(sim->model(), sim->state(), v, &w);
  CHECK(miss.fields.empty());
  REQUIRE(miss.warnings.size() == 1);
  CHECK(miss.warnings[0].find("misses") != std::string::npos);
  // Through the far corner (4, 4, 4) only, to round-off: the same (a sliver of 1e-16 was drawn, blank).
  v.slice_position = 12 / s3;
  const RenderScene corner = build_render_scene(sim->model(), sim->state(), v, &w);
  CHECK(corner.fields.empty());
  REQUIRE(corner.warnings.size() == 1);
  CHECK(corner.warnings[0].find("misses") != std::string::npos);
}

TEST_CASE("[render] slice_normal: any direction, normalised, through the domain centre by default") {
  Model m = test::model_from(std::string(kCube) + "[render]\nslice_normal = [1, 1, 0]\n");
  CHECK(m.render.slice_normal[0] == doctest::Approx(std::sqrt(0.5)));
  CHECK(m.render.slice_normal[1] == doctest::Approx(std::sqrt(0.5)));
  CHECK(m.render.slice_normal[2] == 0);
  CHECK(m.render.slice_position == doctest::Approx(4 * std::sqrt(0.5)));  // n . (2, 2, 2)
  m = test::model_from(std::string(kCube) + "[render]\nslice_axis = \"x\"\nslice_position = 1.5\n");
  CHECK(m.render.slice_normal[0] == 1);
  CHECK(m.render.slice_position == 1.5);
  CHECK(test::scene_error(std::string(kCube) + "[render]\nslice_axis = \"x\"\nslice_normal = [0, 0, 1]\n")
            .find("not both") != std::string::npos);
  CHECK(test::scene_error(std::string(kCube) + "[render]\nslice_normal = [0, 0, 0]\n").find("non-zero") !=
        std::string::npos);
  // A plane that misses the cube drew the box alone: refused. On its faces, it is drawn.
  CHECK(test::scene_error(std::string(kCube) + "[render]\nslice_axis = \"x\"\nslice_position = 5.0\n")
            .find("the slice n . x = 5 misses the domain, where n . x spans [0, 4]") != std::string::npos);
  CHECK(test::scene_error(std::string(kCube) + "[render]\nslice_normal = [1, 1, 0]\nslice_position = -0.1\n")
            .find("misses the domain") != std::string::npos);
  CHECK(test::scene_error(std::string(kCube) + "[render]\nslice_axis = \"z\"\nslice_position = 4.0\n") == "");
}

TEST_CASE("[render] draw: the grains by default, and a fluid's field where the scene has a fluid and no grains") {
  using List = std::vector<std::string>;
  CHECK(test::model_from(kCube).render.draw == List{"grains", "colorbar", "time", "scalebar"});
  // (a fluid alone drew white frames: the grains it has none of, under a speed colour bar)
  const std::string fluid =
      "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [1.0, 1.0]\n[fluid]\ncells = [8, 8]\n"
      "reynolds = 100.0\n[fluid.boundary]\ny_hi_velocity = [1.0, 0.0]\n";
  CHECK(test::model_from(fluid).render.draw == List{"field", "colorbar", "time", "scalebar"});
  CHECK(test::model_from(fluid + "[render]\ndraw = [\"grains\", \"time\"]\n").render.draw == List{"grains", "time"});
}
