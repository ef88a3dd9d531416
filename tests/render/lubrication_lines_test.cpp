// A paste's frame: the lubrication forces (pair_f_lub) drawn apart from the contacts' force
// chains, with their own widths, colours and depth, and their colour bar.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "render/render_support.hpp"
#include "render/scene_parts.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::render;
using silt::test::pixel_of;

namespace {

// The normal lubrication force of every pair that has one, as the frame defines it: f . d / |d|,
// f the force on i from j and d = x_i - x_j (positive: pushed apart).
struct LubricatedPair {
  int i, j;
  double fn;
};
std::vector<LubricatedPair> lubricated_pairs(const State& s) {
  const auto f = double_field(s, find_field("pair_f_lub")->id);
  std::vector<LubricatedPair> out;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      const int j = s.pair_j[p];
      double d[3] = {0, 0, 0}, dist2 = 0, fd = 0;
      for (int a = 0; a < 2; ++a) d[a] = s.particle_x[2 * i + a] - s.particle_x[2 * j + a];
      s.box.nearest(d, 2);
      for (int a = 0; a < 2; ++a) {
        dist2 += d[a] * d[a];
        fd += f[2 * p + a] * d[a];
      }
      if (fd != 0) out.push_back({static_cast<int>(i), j, fd / std::sqrt(dist2)});
    }
  return out;
}

}  // namespace

TEST_CASE("a paste's frame draws its lubrication forces apart from the contacts' chains") {
  auto sim = test::simulation_from(test::kLubricatedFive);
  sim->prepare();
  const State& s = sim->state();
  const std::vector<LubricatedPair> lub = lubricated_pairs(s);
  auto is = [](const LubricatedPair& l, int i, int j) { return (l.i == i && l.j == j) || (l.i == j && l.j == i); };
  REQUIRE(lub.size() == 6);
  double mean = 0;
  for (const LubricatedPair& l : lub) mean += std::abs(l.fn) / static_cast<double>(lub.size());
  // The contacts' normal forces, k_n times the overlaps: 200 and 50, mean 125.
  const double f01 = 1e4 * 0.02, f12 = 1e4 * (1 - std::hypot(0.597, 0.796)), f_mean = 0.5 * (f01 + f12);
  View v = test::plain_view(800, 800, {"chains", "lubrication"});
  const RenderScene rs = build_render_scene(sim->model(), s, v);
  CHECK(rs.warnings.empty());
  // The two contacts first (their chains), then one segment per lubricated pair.
  REQUIRE(rs.segments.size() == 2 + lub.size());
  const double r_max = 0.5, r_mean = 0.5;
  const Colormap& sequential = Colormap::get("sequential");
  const Colormap& diverging = Colormap::get("diverging");
  std::vector<double> chain_widths{rs.segments[0].width, rs.segments[1].width};
  std::sort(chain_widths.begin(), chain_widths.end());
  CHECK(chain_widths[0] == doctest::Approx(0.4 * f12 / f_mean * r_mean).epsilon(1e-6));
  CHECK(chain_widths[1] == doctest::Approx(0.4 * f01 / f_mean * r_mean).epsilon(1e-6));
  for (size_t k = 0; k < 2; ++k) CHECK(rs.segments[k].a[2] == doctest::Approx(2 * r_max));  // in front
  for (size_t k = 0; k < lub.size(); ++k) {
    const RenderScene::Segment& seg = rs.segments[2 + k];
    CAPTURE(k);
    const double rel = lub[k].fn / mean;
    CHECK(seg.a[2] == doctest::Approx(1.5 * r_max));  // behind the contacts' chains
    // Half the contacts' width at the same force relative to its mean; red pushing apart, blue
    // pulling together.
    CHECK(seg.width == doctest::Approx(0.5 * std::min(0.4 * std::abs(rel), kChainMaxWidthRadii) * r_mean));
    CHECK(seg.color == diverging.at(0.5 + 0.5 * std::clamp(rel / kChainColorMax, -1.0, 1.0)));
    CHECK(seg.a[0] == doctest::Approx(s.particle_x[2 * lub[k].i]).epsilon(1e-6));
    CHECK(seg.a[1] == doctest::Approx(s.particle_x[2 * lub[k].i + 1]).epsilon(1e-6));
  }
  // On screen: the middle of a contact (0-1) has its chain's colour, drawn over the lubrication
  // of the same pair. (In this quasi-static cluster the gaps that only lubricate carry forces of
  // 1e-11: the contacts' lubrication balances the contact forces alone, and those segments are
  // thinner than a pixel.)
  Rasterizer raster(1);
  const Image img = raster.draw(rs);
  auto mid = [&](int i, int j) {
    return pixel_of(rs, 0.5 * (s.particle_x[2 * i] + s.particle_x[2 * j]),
                    0.5 * (s.particle_x[2 * i + 1] + s.particle_x[2 * j + 1]));
  };
  for (size_t k = 0; k < lub.size(); ++k) {
    if (is(lub[k], 0, 1)) {
      const auto px = mid(0, 1);
      const size_t chain = rs.segments[0].width > rs.segments[1].width ? 0 : 1;
      CHECK(img.pixel(px[0], px[1]) == rs.segments[chain].color);
      CHECK(rs.segments[chain].color == sequential.at(std::min(1.0, f01 / f_mean / kChainColorMax)));
      CHECK_FALSE(rs.segments[chain].color == rs.segments[2 + k].color);
    }
  }
}

TEST_CASE("the lubrication forces' colour bar, and a dry scene that has none to draw") {
  auto sim = test::simulation_from(test::kLubricatedFive);
  sim->prepare();
  View v = test::plain_view(800, 600, {"lubrication", "colorbar"});
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(rs.colorbar.on);
  CHECK(rs.colorbar.label == "lubrication force / mean");
  CHECK(rs.colorbar.lo == -kChainColorMax);
  CHECK(rs.colorbar.hi == kChainColorMax);
  auto dry = test::simulation_from(test::kRow);
  dry->prepare();
  const RenderScene none = build_render_scene(dry->model(), dry->state(), v);
  CHECK(none.segments.empty());
  REQUIRE(none.warnings.size() == 1);
  CHECK(none.warnings[0] == "no lubrication forces to draw in this scene");
  // No colour bar for what is not drawn (its empty scale made the frame writer throw on a colour
  // map named "": frames stopped, exit 4); a scene that asks for them is refused when read.
  CHECK_FALSE(none.colorbar.on);
  const std::string refused =
      test::scene_error(std::string(test::kRow) + "\n[render]\ndraw = [\"grains\", \"lubrication\"]\n");
  CHECK(refused.find("'lubrication' draws a paste's lubrication forces, but this scene has no [lubrication]") !=
        std::string::npos);
}

TEST_CASE("chains and lubrication drawn with no contact yet: the bar is the lubrication's") {
  // (the bar showed the chains' "normal force / mean" over the lubrication's forces alone)
  // Random disks at an imposed pressure: the box's rate moves them, and none touch yet.
  auto sim = test::simulation_from(test::paste_disks({}));
  sim->prepare();
  View v = test::plain_view(800, 600, {"chains", "lubrication", "colorbar"});
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE_FALSE(rs.segments.empty());  // the lubrication's, random grains touching none
  REQUIRE(rs.colorbar.on);
  CHECK(rs.colorbar.label == "lubrication force / mean");
}

TEST_CASE("chains and lubrication drawn together: a colour bar each, where the frame has room for two") {
  // (only the chains' bar was drawn: the lubrication forces' colours could not be read)
  auto sim = test::simulation_from(test::kLubricatedFive);
  sim->prepare();
  View v = test::plain_view(800, 600, {"chains", "lubrication", "colorbar"});
  const RenderScene rs = build_render_scene(sim->model(), sim->state(), v);
  REQUIRE(rs.colorbar.on);
  CHECK(rs.colorbar.label == "normal force / mean");
  REQUIRE(rs.lubrication_bar.on);
  CHECK(rs.lubrication_bar.label == "lubrication force / mean");
  CHECK(rs.lubrication_bar.x + 100 < rs.colorbar.x);
  // Their labels, wider than the bars are apart, one above the other.
  CHECK(rs.lubrication_bar.y - rs.lubrication_bar.label_above + 13 <= rs.colorbar.y - rs.colorbar.label_above);
  CHECK(rs.camera.domain_px[0] + rs.camera.domain_px[2] <= rs.lubrication_bar.x);  // beside the domain
  // Too narrow for two: the chains' alone, and a warning.
  v.width = 300;
  const RenderScene narrow = build_render_scene(sim->model(), sim->state(), v);
  CHECK(narrow.colorbar.on);
  CHECK_FALSE(narrow.lubrication_bar.on);
  REQUIRE(narrow.warnings.size() == 1);
  CHECK(narrow.warnings[0].find("room for one colour bar, the chains'") != std::string::npos);
}
