// Verlet lists from the cell list against a brute-force search, with periodic images.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <set>

#include "dem/stages.hpp"
#include "silt/periodic_image.hpp"
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

// A box of n grains; `big`: one for more than Model::kSortMin grains (renumbered in cell order).
std::string box_scene(int dim, int seed, int n, bool z_periodic, bool big = false) {
  std::string s = test::fill(kBox, {{"seed", seed}, {"n", n}});
  s.replace(s.find("dimension = {dim}"), 17, "dimension = " + std::to_string(dim));
  s.replace(s.find("LO"), 2, dim == 3 ? "[-3, 0, 1]" : "[-3, 0]");
  s.replace(s.find("HI"), 2, big ? (dim == 3 ? "[10, 12, 11]" : "[37, 36]") : (dim == 3 ? "[5, 7.5, 6]" : "[9, 6.5]"));
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

}  // namespace

TEST_CASE("cell list + Verlet list find exactly the pairs of a brute-force search") {
  for (int dim : {2, 3}) {
    for (bool zper : {false, true}) {
      for (int seed : {1, 2, 3, 4}) {
        CAPTURE(dim);
        CAPTURE(seed);
        // Seed 4: more than Model::kSortMin grains, renumbered in cell order at each build.
        const bool big = seed == 4;
        auto sim = test::simulation_from(box_scene(dim, seed, big ? 1400 : dim == 3 ? 150 : 80, zper, big), 2);
        REQUIRE(big == (sim->model().n_grains > Model::kSortMin));
        sim->prepare();
        for (int round = 0; round < 3; ++round) {
          const State& s = sim->state();
          CHECK(test::listed_pairs(s) == brute_force(sim->model(), s));
          CHECK(static_cast<int64_t>(test::listed_pairs(s).size()) == s.n_pairs());  // no duplicates
          for (int64_t i = 0; i < s.n; ++i)
            CHECK(std::is_sorted(s.pair_j.begin() + s.nbr_start[i], s.pair_j.begin() + s.nbr_start[i + 1]));
          // Move on and force a rebuild.
          for (int k = 0; k < 200; ++k) REQUIRE(sim->step());
          sim->state().nbr_valid = false;
          dem::update_neighbors(sim->model(), sim->state(), test::dem_workspace(*sim));
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
      const auto have = test::listed_pairs(s);
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
  // Every listed pair a contact candidate: otherwise the selection after the rebuild clears the
  // (made-up) springs of the pairs that are apart.
  std::string scene = box_scene(3, 5, 150, true);
  scene.replace(scene.find("skin = 0.3"), 10, "skin = 0.3\ncontact_skin = 0");
  auto sim = test::simulation_from(scene, 1);
  sim->prepare();
  State& s = sim->state();
  for (size_t p = 0; p < s.pair_j.size(); ++p)
    for (int a = 0; a < 3; ++a) s.pair_hist[3 * p + a] = 1000.0 * p + a;
  std::map<std::pair<int, int>, double> before;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p)
      before[{static_cast<int>(i), s.pair_j[p]}] = s.pair_hist[3 * p + 1];
  s.nbr_valid = false;
  dem::update_neighbors(sim->model(), s, test::dem_workspace(*sim));  // same positions: same pairs
  int64_t checked = 0;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      CHECK(s.pair_hist[3 * p + 1] == before.at({static_cast<int>(i), s.pair_j[p]}));
      ++checked;
    }
  CHECK(checked == static_cast<int64_t>(before.size()));
}

TEST_CASE("renumbering grains in cell order keeps forces, histories and identities") {
  // A frictional bed of 1500 grains settling on a wall: persistent contacts with tangential
  // springs. One copy renumbers its grains at a rebuild, the other does not; forces and springs
  // must agree grain by grain and pair by pair (up to the order of summation).
  const char* scene = R"(
[scene]
dimension = 3
seed = 21
[domain]
lo = [0, 0, 0]
hi = [10, 10, 12]
periodic = [true, true, false]
[gravity]
magnitude = 100
[contact]
model = "spring_dashpot"
restitution = 0.5
contact_time = 2e-3
friction = 0.5
[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
[[grains]]
count = 1500
radius_min = 0.3
radius_max = 0.45
placement = "random"
[neighbor]
sort = false
[run]
dt_over_tc = 0.05
)";
  auto a = test::simulation_from(scene, 2);
  for (int k = 0; k < 8000; ++k) REQUIRE(a->step());
  auto b = test::simulation_from(scene, 2);
  b->restore(a->state());
  // Renumber in a, not in b.
  a->model_for_steering().sort_grains = true;
  for (auto* sim : {a.get(), b.get()}) {
    sim->state().nbr_valid = false;
    dem::update_neighbors(sim->model(), sim->state(), test::dem_workspace(*sim));
    dem::contact_forces(sim->model(), sim->state(), test::dem_workspace(*sim));
    dem::wall_forces(sim->model(), sim->state());
    dem::sum_forces(sim->model(), sim->state(), {{fid::wall_f, fid::particle_t_wall}});
  }
  const State& sa = a->state();
  const State& sb = b->state();
  const auto ia = index_of_ids(sa);
  bool moved = false;
  for (int64_t i = 0; i < sa.n; ++i) moved = moved || ia[i] != i;
  CHECK(moved);
  double fmax = 0;
  for (double f : sb.particle_f) fmax = std::max(fmax, std::abs(f));
  for (int64_t id = 0; id < sb.n; ++id)
    for (int k = 0; k < 3; ++k) {
      REQUIRE(sa.particle_x[3 * ia[id] + k] == sb.particle_x[3 * id + k]);
      CHECK(std::abs(sa.particle_f[3 * ia[id] + k] - sb.particle_f[3 * id + k]) <= 1e-12 * fmax);
      CHECK(std::abs(sa.particle_t[3 * ia[id] + k] - sb.particle_t[3 * id + k]) <= 1e-12 * fmax);
    }
  // Springs by pair of ids, oriented from the smaller id.
  std::map<std::pair<int, int>, Vec3> springs;
  int64_t stretched = 0;
  for (int64_t i = 0; i < sb.n; ++i)
    for (int32_t p = sb.nbr_start[i]; p < sb.nbr_start[i + 1]; ++p) {
      springs[{static_cast<int>(i), sb.pair_j[p]}] = at<3>(sb.pair_hist.data(), p);
      stretched += at<3>(sb.pair_hist.data(), p).norm() > 0;
    }
  CHECK(stretched > 100);
  for (int64_t i = 0; i < sa.n; ++i)
    for (int32_t p = sa.nbr_start[i]; p < sa.nbr_start[i + 1]; ++p) {
      const int idi = sa.particle_id[i], idj = sa.particle_id[sa.pair_j[p]];
      const Vec3 h = at<3>(sa.pair_hist.data(), p);
      const Vec3 expect = idi < idj ? springs.at({idi, idj}) : Vec3(-springs.at({idj, idi}));
      CHECK((h - expect).norm() <= 1e-15 + 1e-12 * expect.norm());
    }
}

namespace {

// A workspace of another module, made for the grains' order: it counts what it is told.
struct OrderProbe final : Workspace {
  int invalidations = 0;
  void invalidate() override { ++invalidations; }
  size_t bytes() const override { return 0; }
};

}  // namespace

TEST_CASE("a renumbering of the grains invalidates the other modules' workspaces, not the DEM's") {
  auto sim = test::simulation_from(box_scene(3, 6, 1400, true, true), 1);
  // The access check runs a stage twice (on a poisoned copy, then for real): one renumbering would
  // be told twice, as it is under the sanitizers. This test counts, so it runs each stage once.
  sim->set_access_check(false);
  sim->prepare();
  OrderProbe& probe = sim->workspaces().get<OrderProbe>();
  dem::DemWorkspace& dem = test::dem_workspace(*sim);
  int renumberings = 0;
  for (int k = 0; k < 3000 && renumberings < 2; ++k) {
    const int64_t builds = sim->state().nbr_builds;
    const std::vector<int32_t> perm = dem.perm;
    const int before = probe.invalidations;
    REQUIRE(sim->step());
    const bool renumbered = sim->state().nbr_builds != builds && dem.perm != perm;
    CHECK(probe.invalidations == before + (renumbered ? 1 : 0));
    renumberings += renumbered;
    if (renumbered) CHECK(dem.schedule_valid);  // the DEM keeps what the rebuild made
  }
  CHECK(renumberings == 2);
}
