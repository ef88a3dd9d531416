// Verlet lists from the cell list against a brute-force search, with periodic images.
#include <doctest/doctest.h>

#include <algorithm>
#include <set>

#include "dem/box_geometry.hpp"
#include "dem/stages.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

const char* kBox = R"(
[scene]
dimension = {dim}
seed = {seed}
[domain]
lo = LO
hi = HI
periodic = PER
[contact]
model = "hooke"
k_n = 1e4
friction = 0.3
[[grains]]
count = {n}
radius_min = 0.2
radius_max = 0.5
placement = "random"
velocity = "gaussian"
temperature = 1
[neighbor]
skin = 0.3
[run]
dt = 1e-3
)";

std::string box_scene(int dim, int seed, int n, bool z_periodic) {
  std::string s = test::fill(kBox, {{"seed", seed}, {"n", n}});
  s.replace(s.find("dimension = {dim}"), 17, "dimension = " + std::to_string(dim));
  s.replace(s.find("LO"), 2, dim == 3 ? "[-3, 0, 1]" : "[-3, 0]");
  s.replace(s.find("HI"), 2, dim == 3 ? "[5, 7.5, 6]" : "[9, 6.5]");
  s.replace(s.find("PER"), 3, dim == 3 ? (z_periodic ? "[true, true, true]" : "[true, false, true]") : "[true, true]");
  return s;
}

std::set<std::pair<int, int>> brute_force(const Model& m, const State& s) {
  std::set<std::pair<int, int>> out;
  for (int64_t i = 0; i < s.n; ++i)
    for (int64_t j = i + 1; j < s.n; ++j) {
      double d2 = 0;
      for (int k = 0; k < m.dim; ++k) {
        double d = s.particle_x[m.dim * i + k] - s.particle_x[m.dim * j + k];
        if (s.box.periodic[k]) d -= s.box.len[k] * std::nearbyint(d / s.box.len[k]);
        d2 += d * d;
      }
      const double reach = s.particle_r[i] + s.particle_r[j] + m.skin;
      if (d2 < reach * reach) out.insert({static_cast<int>(i), static_cast<int>(j)});
    }
  return out;
}

std::set<std::pair<int, int>> listed(const State& s) {
  std::set<std::pair<int, int>> out;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) out.insert({static_cast<int>(i), s.pair_j[p]});
  return out;
}

}  // namespace

TEST_CASE("cell list + Verlet list find exactly the pairs of a brute-force search") {
  for (int dim : {2, 3}) {
    for (bool zper : {false, true}) {
      for (int seed : {1, 2, 3}) {
        CAPTURE(dim);
        CAPTURE(seed);
        auto sim = test::simulation_from(box_scene(dim, seed, dim == 3 ? 150 : 80, zper), 2);
        sim->prepare();
        for (int round = 0; round < 3; ++round) {
          const State& s = sim->state();
          CHECK(listed(s) == brute_force(sim->model(), s));
          CHECK(static_cast<int64_t>(listed(s).size()) == s.n_pairs());  // no duplicates
          for (int64_t i = 0; i < s.n; ++i)
            CHECK(std::is_sorted(s.pair_j.begin() + s.nbr_start[i], s.pair_j.begin() + s.nbr_start[i + 1]));
          // Move on and force a rebuild.
          for (int k = 0; k < 200; ++k) REQUIRE(sim->step());
          sim->state().nbr_valid = false;
          dem::update_neighbors(sim->model(), sim->state());
        }
      }
    }
  }
}

TEST_CASE("a list is kept until a grain moved half the skin, and every contact is in it") {
  auto sim = test::simulation_from(box_scene(3, 4, 150, true), 1);
  sim->prepare();
  int64_t builds = sim->state().nbr_builds;
  for (int k = 0; k < 2000; ++k) {
    REQUIRE(sim->step());
    const State& s = sim->state();
    if (s.nbr_builds == builds) CHECK(2 * s.nbr_max_disp <= sim->model().skin);
    builds = s.nbr_builds;
    if (k % 50 == 0) {
      // Every touching pair must be listed.
      const auto all = brute_force(sim->model(), s);
      const auto have = listed(s);
      for (auto [i, j] : all) {
        double d2 = 0;
        for (int a = 0; a < 3; ++a) {
          double d = s.particle_x[3 * i + a] - s.particle_x[3 * j + a];
          d -= s.box.len[a] * std::nearbyint(d / s.box.len[a]);
          d2 += d * d;
        }
        if (std::sqrt(d2) < s.particle_r[i] + s.particle_r[j]) CHECK(have.count({i, j}) == 1);
      }
    }
  }
  CHECK(sim->state().nbr_builds > 3);
}

TEST_CASE("tangential histories survive a rebuild of the list") {
  auto sim = test::simulation_from(box_scene(3, 5, 150, true), 1);
  sim->prepare();
  State& s = sim->state();
  for (size_t p = 0; p < s.pair_j.size(); ++p)
    for (int a = 0; a < 3; ++a) s.pair_hist[3 * p + a] = 1000.0 * p + a;
  std::map<std::pair<int, int>, double> before;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) before[{static_cast<int>(i), s.pair_j[p]}] = s.pair_hist[3 * p + 1];
  s.nbr_valid = false;
  dem::update_neighbors(sim->model(), s);  // same positions: same pairs
  int64_t checked = 0;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      CHECK(s.pair_hist[3 * p + 1] == before.at({static_cast<int>(i), s.pair_j[p]}));
      ++checked;
    }
  CHECK(checked == static_cast<int64_t>(before.size()));
}
