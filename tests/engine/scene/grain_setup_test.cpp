// Grains of a scene: counts, radii distributions, masses, placements.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "support/scenes.hpp"

using namespace silt;

namespace {

const char* kBase = R"(
[scene]
dimension = 3
seed = 3
[domain]
lo = [0, 0, 0]
hi = [20, 20, 20]
periodic = [true, true, true]
[contact]
model = "hooke"
k_n = 1e5
[[grains]]
count = 2000
GRAINS
density = 2.0
[run]
dt = 1e-4
)";

Model with_grains(const std::string& grains) {
  std::string s = kBase;
  s.replace(s.find("GRAINS"), 6, grains);
  return test::model_from(s);
}

}  // namespace

TEST_CASE("the chute has LAMMPS's 800 frozen base grains and 16,800 bed grains") {
  const Model m = compile(load_scene_file(test::scene_path("chute")));
  CHECK(m.n_grains == 17600);
  CHECK(m.n_frozen == 800);
  // Base at z = 0, bed on z = 1 .. 21, on the unit simple cubic lattice.
  double zmin = 1e9, zmax = -1e9;
  for (int64_t i = 0; i < m.n_grains; ++i) {
    const double z = m.init.x[3 * i + 2];
    if (m.init.frozen[i]) CHECK(z == 0.0);
    else {
      zmin = std::min(zmin, z);
      zmax = std::max(zmax, z);
    }
  }
  CHECK(zmin == 1.0);
  CHECK(zmax == 21.0);
  // Mass of a sphere of diameter 0.98 at density 1.9099 (= 6/pi): 0.98^3.
  CHECK(m.init.mass[0] == doctest::Approx(1.9099 * std::numbers::pi / 6 * std::pow(0.98, 3)));
  CHECK(m.init.inertia[0] == doctest::Approx(0.4 * m.init.mass[0] * 0.49 * 0.49));
}

TEST_CASE("radius distributions: uniform, bidisperse by volume fraction, explicit") {
  const Model u = with_grains("radius_min = 0.2\nradius_max = 0.3");
  double lo = 1, hi = 0, mean = 0;
  for (double r : u.init.radius) {
    lo = std::min(lo, r);
    hi = std::max(hi, r);
    mean += r / u.n_grains;
  }
  CHECK(lo >= 0.2);
  CHECK(hi <= 0.3);
  CHECK(mean == doctest::Approx(0.25).epsilon(0.01));  // 2000 draws: error ~ 0.029/sqrt(2000)
  // Bidisperse: 30 % of the grain volume in the large grains (radius 0.4), 70 % in the small (0.2).
  const Model b = with_grains("radii = [0.2, 0.4]\nvolume_fractions = [0.7, 0.3]");
  double v_large = 0, v_total = 0;
  int64_t n_large = 0;
  for (double r : b.init.radius) {
    v_total += r * r * r;
    if (r == 0.4) {
      v_large += r * r * r;
      ++n_large;
    }
  }
  CHECK(v_large / v_total == doctest::Approx(0.3).epsilon(0.01));
  CHECK(n_large + std::count(b.init.radius.begin(), b.init.radius.end(), 0.2) == 2000);
  // Mass and inertia of a sphere.
  CHECK(b.init.mass[0] == doctest::Approx(2.0 * 4.0 / 3.0 * std::numbers::pi * std::pow(b.init.radius[0], 3)));
  CHECK(b.init.inertia[0] == doctest::Approx(0.4 * b.init.mass[0] * b.init.radius[0] * b.init.radius[0]));
  const Model e = test::model_from(R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [10, 10]
[contact]
model = "linear"
k_n = 100
[[grains]]
radius_list = [0.5, 0.25]
placement = "explicit"
positions = [[2, 2], [5, 5]]
density = 3.0
[run]
dt = 1e-3
)");
  REQUIRE(e.n_grains == 2);
  CHECK(e.init.mass[1] == doctest::Approx(3.0 * std::numbers::pi * 0.0625));   // disk: rho pi r^2
  CHECK(e.init.inertia[1] == doctest::Approx(0.5 * e.init.mass[1] * 0.0625));  // m r^2 / 2
}

TEST_CASE("random placement never overlaps, wraps periodic directions, and depends only on the seed") {
  const Model a = with_grains("radius_min = 0.3\nradius_max = 0.6\nplacement = \"random\"");
  const Model b = with_grains("radius_min = 0.3\nradius_max = 0.6\nplacement = \"random\"");
  CHECK(a.init.x == b.init.x);
  int64_t overlaps = 0;
  for (int64_t i = 0; i < a.n_grains; ++i)
    for (int64_t j = i + 1; j < a.n_grains; ++j) {
      double d2 = 0;
      for (int k = 0; k < 3; ++k) {
        double d = a.init.x[3 * i + k] - a.init.x[3 * j + k];
        d -= 20 * std::nearbyint(d / 20);
        d2 += d * d;
      }
      overlaps += std::sqrt(d2) < a.init.radius[i] + a.init.radius[j];
    }
  CHECK(overlaps == 0);
  for (double x : a.init.x) CHECK((x >= 0 && x < 20));
}

TEST_CASE("lattices: square, triangular (2D) and fcc (3D) fill the half-open region") {
  const Model sc = with_grains(
      "radius = 0.25\nplacement = \"lattice\"\nlattice = \"sc\"\nspacing = 1.0\nregion_lo = [0, 0, 0]\nregion_hi = "
      "[20, 20, 5]");
  CHECK(sc.n_grains == 2000);  // count = 2000 of the 20 x 20 x 5 = 2000 sites
  // 14 fcc cells across the periodic box of 20: spacing 20 / (14 sqrt 2).
  const Model fcc = with_grains(
      "radius = 0.25\nplacement = \"lattice\"\nlattice = \"fcc\"\nspacing = 1.0101525445522108\nregion_lo = [0, 0, "
      "0]\nregion_hi = [20, 20, 20]");
  // Nearest neighbours of the fcc lattice at distance `spacing`.
  double dmin = 1e9;
  for (int64_t j = 1; j < 200; ++j) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += std::pow(fcc.init.x[k] - fcc.init.x[3 * j + k], 2);
    dmin = std::min(dmin, std::sqrt(d2));
  }
  CHECK(dmin == doctest::Approx(1.0101525445522108));
  const Model off = with_grains(
      "radius = 0.25\nplacement = \"lattice\"\nspacing = 1.0\nlattice_origin = [0.5, 0.5, 0.5]\nregion_lo = [0, 0, "
      "0]\nregion_hi = [20, 20, 5]");
  CHECK(off.init.x[0] == 0.5);
  CHECK_THROWS_WITH_AS(with_grains("radius = 0.25\nplacement = \"lattice\"\nspacing = 1.0\nregion_hi = [5, 5, 5]"),
                       doctest::Contains("holds only 125 sites"), SceneError);
}
