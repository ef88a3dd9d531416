// Materials: groups and walls of their own modulus, stiffness and friction, mixed by the rules of
// dem/materials.hpp, and collisions that last as the mixed law says.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "dem/contact_laws.hpp"
#include "dem/materials.hpp"
#include "silt/observables.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// Two spheres of radius 1 mm in two groups approaching head-on at 2 v (Hertz).
const char* kHertzGroups = R"(
[scene]
dimension = 3
[domain]
lo = [-1, -1, -1]
hi = [1, 1, 1]
[contact]
model = "hertz"
young_modulus = 7e10
poisson_ratio = 0.3
[[grains]]
radius = 1e-3
density = 2500
placement = "explicit"
positions = [[-1.00001e-3, 0, 0]]
velocity = "explicit"
velocities = [[{v}, 0, 0]]
[[grains]]
radius = 1e-3
density = 2500
young_modulus = {e2}
poisson_ratio = 0.2
placement = "explicit"
positions = [[1.00001e-3, 0, 0]]
velocity = "explicit"
velocities = [[-{v}, 0, 0]]
[run]
dt = {dt}
)";

// A sphere dropped on a wall (no gravity: it moves toward it at v).
const char* kWall = R"(
[scene]
dimension = 3
[domain]
lo = [-1, -1, 0]
hi = [1, 1, 1]
[contact]
{law}
[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
{wall}
[[grains]]
radius = 1e-3
density = 2500
placement = "explicit"
positions = [[0, 0, 1.0001e-3]]
velocity = "explicit"
velocities = [[0, 0, -0.1]]
[run]
dt = 1e-8
)";

// Steps until the grain leaves the wall; returns the contact duration.
double wall_contact_time(Simulation& sim) {
  const State& s = sim.state();
  int64_t touching = 0;
  for (int64_t k = 0; k < 10'000'000; ++k) {
    REQUIRE(sim.step());
    const bool touch = s.particle_x[2] < s.particle_r[0];
    if (touch) ++touching;
    else if (touching) break;
  }
  return touching * s.dt;
}

std::string wall_scene(const std::string& law, const std::string& wall) {
  std::string s = kWall;
  s.replace(s.find("{law}"), 5, law);
  s.replace(s.find("{wall}"), 6, wall);
  return s;
}

}  // namespace

TEST_CASE("materials: the mixing rules, and one material mixed with itself is itself") {
  ContactParams hz;
  hz.law = NormalLaw::kHertz;
  hz.e_tilde = 7e10 / (1 - 0.09);
  const Material steel{(1 - 0.09) / 7e10, 0, 0.4}, rubber{(1 - 0.25) / 1e7, 0, 0.9}, rigid{0, 0, 0.4};
  CHECK(dem::mix(hz, steel, steel).e_tilde == doctest::Approx(hz.e_tilde).epsilon(1e-14));
  CHECK(dem::mix(hz, steel, rigid).e_tilde == doctest::Approx(2 * hz.e_tilde).epsilon(1e-14));
  CHECK(dem::mix(hz, steel, rubber).e_tilde == doctest::Approx(2 / ((1 - 0.09) / 7e10 + 0.75 / 1e7)).epsilon(1e-14));
  CHECK(dem::mix(hz, steel, rubber).friction == 0.4);
  ContactParams lin;
  lin.law = NormalLaw::kLinear;
  const Material a{0, 1e4, 0.3}, b{0, 3e4, 0.5};
  CHECK(dem::mix(lin, a, a).k0 == doctest::Approx(1e4).epsilon(1e-14));
  CHECK(dem::mix(lin, a, b).k0 == doctest::Approx(1.5e4).epsilon(1e-14));
  // A rigid wall: the limit of the series rule, 2 k_grain (it was k_grain, softer than a stiff wall)
  CHECK(dem::mix(lin, a, Material{0, 0, 0.5}).k0 == 2e4);
  CHECK(dem::mix(lin, a, Material{0, 1e12, 0.5}).k0 == doctest::Approx(2e4).epsilon(1e-7));
}

TEST_CASE("materials: a Hertz collision of two materials lasts as the mixed modulus says") {
  const double r = 1e-3, m = 2500 * 4.0 / 3.0 * std::numbers::pi * r * r * r, m_eff = m / 2, v = 0.1;
  for (double e2 : {7e10, 1e9}) {
    CAPTURE(e2);
    const double e_pair = 2 / ((1 - 0.09) / 7e10 + (1 - 0.04) / e2);
    const double kh = e_pair / 3 * std::sqrt(2 * r);  // R_eq = r
    const double tc = dem::hertz_duration() * std::pow(m_eff / kh, 0.4) * std::pow(2 * v, -0.2);
    auto sim = test::simulation_from(test::fill(kHertzGroups, {{"v", v}, {"e2", e2}, {"dt", tc / 20000}}));
    CHECK(sim->model().pair_contact.size() == 4);
    const auto c = test::head_on_collision(*sim, 2 * v);
    CHECK(c.duration == doctest::Approx(tc).epsilon(2e-4));
  }
}

TEST_CASE("materials: a rigid wall doubles the Hertz modulus and a wall's spring is in series with the grain's") {
  const double r = 1e-3, m = 2500 * 4.0 / 3.0 * std::numbers::pi * r * r * r, v = 0.1;
  const std::string hertz = "model = \"hertz\"\nyoung_modulus = 7e10\npoisson_ratio = 0.3";
  for (bool rigid : {false, true}) {
    CAPTURE(rigid);
    const double e_pair = (rigid ? 2 : 1) * 7e10 / (1 - 0.09);
    const double kh = e_pair / 3 * std::sqrt(2 * 2 * r);  // R_eq = 2 r against a wall
    const double tc = dem::hertz_duration() * std::pow(m / kh, 0.4) * std::pow(v, -0.2);
    auto sim = test::simulation_from(wall_scene(hertz, rigid ? "rigid = true" : ""));
    CHECK(wall_contact_time(*sim) == doctest::Approx(tc).epsilon(1e-3));
  }
  // Linear springs: k_n = 1e3 for the grains, 3e3 for the wall: 1.5e3 in series.
  auto sim = test::simulation_from(wall_scene("model = \"linear\"\nk_n = 1e3", "k_n = 3e3"));
  CHECK(wall_contact_time(*sim) == doctest::Approx(std::numbers::pi / std::sqrt(1.5e3 / m)).epsilon(1e-3));
  // and against a rigid wall, twice the grain's
  auto stiff = test::simulation_from(wall_scene("model = \"linear\"\nk_n = 1e3", "rigid = true"));
  CHECK(wall_contact_time(*stiff) == doctest::Approx(std::numbers::pi / std::sqrt(2e3 / m)).epsilon(1e-3));
  // What a law does not have is refused.
  CHECK(test::scene_error(wall_scene("model = \"linear\"\nk_n = 1e3", "young_modulus = 1e9")).find("not used") !=
        std::string::npos);
}

TEST_CASE("materials: frictions mix to the smaller, and the run does not depend on the threads") {
  std::string scene = test::frictional_gas(3, 0.5, 0.0, 0.0);
  // Two groups: the gas's, and one more of slippery, stiffer grains.
  scene += R"(
[[grains]]
count = 100
radius = 0.35
friction = 0.05
k_n = 3e4
placement = "random"
)";
  const Model m = test::model_from(scene);
  REQUIRE(m.pair_contact.size() == 4);
  CHECK(m.pair_contact[1].friction == 0.05);
  CHECK(m.pair_contact[2].friction == 0.05);
  CHECK(m.pair_contact[0].friction == m.contact.friction);
  uint64_t h1 = 0;
  for (int threads : {1, 2}) {
    auto sim = test::simulation_from(scene, threads);
    sim->set_access_check(true);
    for (int k = 0; k < 300; ++k) REQUIRE(sim->step());
    if (threads == 1) h1 = state_hash(sim->state());
    else CHECK(state_hash(sim->state()) == h1);
  }
}

TEST_CASE("materials: e_contact holds each contact's own law, so ke + e_contact is kept against a rigid wall") {
  // The energy took the scene's law for every contact: against a rigid Hertz wall (E~ doubled in
  // the force, not in the energy) half the energy went missing at the deepest compression.
  for (const std::string& wall : {std::string("rigid = true"), std::string("young_modulus = 1e9")}) {
    CAPTURE(wall);
    auto sim = test::simulation_from(wall_scene("model = \"hertz\"\nyoung_modulus = 7e10\npoisson_ratio = 0.3", wall));
    const Observer obs(sim->model(), {"ke", "e_contact"});
    const double e0 = obs.sample(sim->model(), sim->state())[0];
    double lo = e0, hi = e0, stored = 0;
    for (int k = 0; k < 4000; ++k) {
      REQUIRE(sim->step());
      const auto v = obs.sample(sim->model(), sim->state());
      lo = std::min(lo, v[0] + v[1]);
      hi = std::max(hi, v[0] + v[1]);
      stored = std::max(stored, v[1]);
    }
    CHECK(stored > 0.5 * e0);  // the collision reached its deepest compression
    CHECK((hi - lo) / e0 < 1e-3);
  }
}

TEST_CASE("materials: a frozen grain on a wall is no contact (the wall exerts no force on it)") {
  std::string scene = wall_scene("model = \"linear\"\nk_n = 1e3", "");
  scene.replace(scene.find("positions = [[0, 0, 1.0001e-3]]"), 31, "frozen = true\npositions = [[0, 0, 0.9e-3]]");
  auto sim = test::simulation_from(scene);
  REQUIRE(sim->state().particle_frozen[0]);
  REQUIRE(sim->step());
  const Observer obs(sim->model(), {"n_contacts", "e_contact"});
  const auto v = obs.sample(sim->model(), sim->state());
  CHECK(v[0] == 0);
  CHECK(v[1] == 0);
}
