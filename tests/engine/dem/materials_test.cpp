// Materials: groups and walls of their own modulus, stiffness and friction, mixed by the rules of
// dem/materials.hpp, and collisions that last as the mixed law says.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "dem/contact_laws.hpp"
#include "dem/contact_setup.hpp"
#include "dem/materials.hpp"
#include "dem/module.hpp"
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

namespace {

// Two groups of their own springs and sizes on a floor: "big" (radius {rb}, k_n {kb}, friction
// {mub}) and "small" (radius 0.1, k_n {ks}, friction {mus}); the floor's spring {kw}.
const char* kTwoGroups = R"(
[scene]
dimension = 3
[domain]
lo = [-10, -10, 0]
hi = [10, 10, 10]
[gravity]
magnitude = {g}
[contact]
model = "linear"
k_n = 1e4
damping = 0.1
friction = 0.5
kt_over_kn = 1.0
[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
k_n = {kw}
[[grains]]
radius = {rb}
density = 1000
k_n = {kb}
friction = {mub}
placement = "explicit"
positions = [[-5, 0, 5], [-2, 0, 5]]
[[grains]]
radius = 0.1
density = 1000
k_n = {ks}
friction = {mus}
placement = "explicit"
positions = [[3, 0, 5], [5, 0, 5]]
[run]
dt = 1e-5
)";

// The velocity-Verlet limit of a spring k on a reduced mass m* with damping ratio zeta.
double limit(double k, double m_eff, double zeta) { return 2 / std::sqrt(k / m_eff) / (std::hypot(1.0, zeta) + zeta); }

}  // namespace

TEST_CASE("materials: each pair of groups' stability limit is of its own law and its own lightest pair") {
  const double m_big = 1000 * 4.0 / 3 * std::numbers::pi;
  // A stiff group of heavy grains and a soft one of light grains: the limit was the stiff law
  // with the light pair's m*, about 30 times too short. Each pair's own: big-big's tangential mode
  // (k_t = k_n, 3.5 k_t on m* = m / 2, no tangential dashpot) is the shortest here.
  Model m = test::model_from(test::fill(
      kTwoGroups, {{"g", 0.0}, {"rb", 1.0}, {"kb", 1e6}, {"mub", 0.5}, {"ks", 1e2}, {"mus", 0.5}, {"kw", 1e9}}));
  CHECK(m.dt_stable_tangential);
  CHECK(m.dt_stable == doctest::Approx(limit(3.5e6, m_big / 2, 0)).epsilon(1e-9));
  // Frictionless groups (friction 0 on both, the scene's 0.5 applying to no pair): no tangential
  // mode; the shortest normal one, big-big's (its dashpot 0.1 of critical).
  m = test::model_from(test::fill(
      kTwoGroups, {{"g", 0.0}, {"rb", 1.0}, {"kb", 1e6}, {"mub", 0.0}, {"ks", 1e2}, {"mus", 0.0}, {"kw", 1e9}}));
  CHECK_FALSE(m.dt_stable_tangential);
  CHECK(m.dt_stable == doctest::Approx(limit(1e6, m_big / 2, 0.1)).epsilon(1e-9));
}

TEST_CASE("materials: a floor's weight check takes each grain with its own group's law") {
  // The heavy group alone overlaps a soft floor: named, with its grain (the mean mass of both
  // groups, checked before, let it pass, and the run failed when the heavy grains landed).
  const std::string e = test::scene_error(test::fill(
      kTwoGroups, {{"g", 9.81}, {"rb", 1.0}, {"kb", 1e6}, {"mub", 0.5}, {"ks", 1e6}, {"mus", 0.5}, {"kw", 5e4}}));
  CHECK(e.find("the weight of grain 0 (of grains[0]) alone presses it into walls[0]") != std::string::npos);
  CHECK(e.find("walls[0].k_n") != std::string::npos);
  // The same floor under grains of the light size alone holds (0.004 of a radius).
  std::string light = test::fill(
      kTwoGroups, {{"g", 9.81}, {"rb", 0.1}, {"kb", 1e6}, {"mub", 0.5}, {"ks", 1e6}, {"mus", 0.5}, {"kw", 5e4}});
  CHECK(test::scene_error(light).empty());
}

TEST_CASE("materials: a Hertz wall's weight check is the static overlap, (3 m g / (E~ sqrt(4 r)))^(2/3)") {
  // A sphere of radius 5 mm and 2,500 kg/m^3 resting on a soft wall of modulus E_w: the overlap
  // reaches 0.2 r (limits.max_overlap) at E~ = 3 m g / (sqrt(4 r) (0.2 r)^(3/2)); E~ of the pair
  // 2 / ((1 - nu_g^2) / E_g + (1 - nu_w^2) / E_w), nu = 0.3 for both.
  const double pi = std::numbers::pi, r = 5e-3, mass = 2500 * 4.0 / 3 * pi * r * r * r, g = 9.81;
  const double e_pair = 3 * mass * g / (std::sqrt(4 * r) * std::pow(0.2 * r, 1.5));
  const double e_g = 7e10, nu2 = 0.09;
  const double e_wall = (1 - nu2) / (2 / e_pair - (1 - nu2) / e_g);  // the wall modulus that gives it
  const char* scene = R"(
[scene]
dimension = 3
[domain]
lo = [0, 0, 0]
hi = [0.1, 0.1, 0.1]
[gravity]
magnitude = 9.81
[contact]
model = "hertz"
young_modulus = 7e10
poisson_ratio = 0.3
[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
young_modulus = {ew}
poisson_ratio = 0.3
[[grains]]
radius = 5e-3
density = 2500
placement = "explicit"
positions = [[0.05, 0.05, 0.05]]
[run]
dt = 1e-7
)";
  CHECK(test::scene_error(test::fill(scene, {{"ew", 1.02 * e_wall}})).empty());
  CHECK(test::scene_error(test::fill(scene, {{"ew", 0.98 * e_wall}})).find("walls[0].young_modulus") !=
        std::string::npos);
}

TEST_CASE("check's weight overlap of Hertz spheres is their static overlap, (m g / k_h)^(2/3) / r") {
  // Two spheres of radius 1 mm, 2,500 kg/m^3, E = 1e7 Pa, nu = 0.3: k_h = (E~ / 3) sqrt(2 r) for a
  // sphere on a like one. The stiffest contact's stiffness at the largest allowed overlap gave
  // m g / (k r) = 2.96e-5 here, 25 times below.
  const double pi = std::numbers::pi, r = 1e-3, mass = 2500 * 4.0 / 3 * pi * r * r * r;
  const double kh = 1e7 / (1 - 0.09) / 3 * std::sqrt(2 * r);
  const double expected = std::pow(mass * 9.81 / kh, 2.0 / 3) / r;
  const Model m = test::model_from(R"(
[scene]
dimension = 3
[domain]
lo = [-0.01, -0.01, -0.01]
hi = [0.01, 0.01, 0.01]
[contact]
model = "hertz"
young_modulus = 1e7
poisson_ratio = 0.3
[gravity]
magnitude = 9.81
[[walls]]
point = [0, 0, -0.005]
normal = [0, 0, 1]
[[grains]]
radius = 1e-3
density = 2500
placement = "explicit"
positions = [[0, 0, 0], [0, 0, 0.003]]
)");
  const std::string text = describe(m);
  const std::string label = "weight overlap (m g / k_h)^(2/3) / r = ";
  const size_t at = text.find(label);
  REQUIRE(at != std::string::npos);
  CHECK(std::stod(text.substr(at + label.size())) == doctest::Approx(expected).epsilon(1e-4));
}

TEST_CASE("materials: t_c is the shortest collision of the groups' laws, kappa and friction their ranges") {
  // Every group gives its own spring: [contact]'s k_n = 1e4 is no pair's. t_c (run.dt_over_tc's
  // unit) was that spring's with the lightest m*, pi sqrt(m_small / 2 / 1e4) = 0.045 s, three times
  // shorter than any collision of the scene; it is now big on big's, the shortest of the three.
  const double pi = std::numbers::pi, m_big = 1000 * 4.0 / 3 * pi, m_small = m_big / 1000;
  const Model m = test::model_from(test::fill(
      kTwoGroups, {{"g", 0.0}, {"rb", 1.0}, {"kb", 1e6}, {"mub", 0.5}, {"ks", 1e2}, {"mus", 0.2}, {"kw", 1e9}}));
  const double big_big = pi * std::sqrt(m_big / 2 / 1e6), small_small = pi * std::sqrt(m_small / 2 / 1e2);
  const double k_mixed = 2 * 1e6 * 1e2 / (1e6 + 1e2);
  const double big_small = pi * std::sqrt(m_big * m_small / (m_big + m_small) / k_mixed);
  REQUIRE(big_big < std::min(small_small, big_small));
  CHECK(m.t_contact == doctest::Approx(big_big).epsilon(1e-12));
  CHECK(m.tc_pair.group_i == 0);
  CHECK(m.tc_pair.group_j == 0);
  CHECK(m.dt == doctest::Approx(1e-5));  // (given as run.dt here)
  // kappa = k_n / (a P), a = 2: the softest pair (small on small) to the stiffest (big on big).
  CHECK(stiffness_number(m, 1.0) == doctest::Approx(1e2 / 2).epsilon(1e-12));
  CHECK(stiffness_number(m, 1.0, true) == doctest::Approx(1e6 / 2).epsilon(1e-12));
  const std::string text = dem::describe_dem(m);
  CHECK(text.find("mu = 0.2 to 0.5 by pair of groups") != std::string::npos);
  CHECK(text.find("shortest collision: grains[0] on grains[0]") != std::string::npos);
}

TEST_CASE("materials: a pressure is checked against the softest pair of groups' kappa") {
  // [contact]'s k_n = 1e4 passed a pressure of 1 (kappa 1e4), while a group of springs of 0.5 is
  // pressed by two diameters (kappa 0.5) and the run failed at its first overlap.
  const char* scene = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [20, 20]
periodic = [true, true]
[box]
pressure = 1.0
[contact]
model = "linear"
k_n = 1e4
damping = 0.5
[[grains]]
count = 20
radius = 0.5
[[grains]]
count = 20
radius = 0.5
k_n = {k}
)";
  const std::string e = test::scene_error(test::fill(scene, {{"k", 0.5}}));
  CHECK(e.find("kappa = 0.5 below 1") != std::string::npos);
  CHECK(e.find("or stiffen the contacts: raise grains[1].k_n") != std::string::npos);  // the softest pair's
  CHECK(test::scene_error(test::fill(scene, {{"k", 5.0}})).empty());
}

TEST_CASE("materials: with no two grains to touch, t_c is the grain's collision with a wall of its materials") {
  // One disk of its own spring 300 on a rigid floor (2 x 300 in series' limit): t_c was [contact]'s
  // spring of 1000 with the disk's mass, pi sqrt(m / 1000), where the bounce lasts pi sqrt(m / 600).
  const char* scene = R"(
[scene]
dimension = 2
[domain]
lo = [-1, 0]
hi = [1, 2]
[contact]
model = "linear"
k_n = 1000
[[walls]]
point = [0, 0]
normal = [0, 1]
rigid = true
[[grains]]
radius = 0.1
density = 100
placement = "explicit"
positions = [[0, 0.11]]
k_n = 300
[run]
dt_over_tc = 0.01
steps = 10
)";
  const double mass = 100 * std::numbers::pi * 0.01;
  const Model m = test::model_from(scene);
  CHECK(m.t_contact == doctest::Approx(std::numbers::pi * std::sqrt(mass / 600)).epsilon(1e-12));
  CHECK(m.tc_pair.wall == 0);
  CHECK(m.dt == doctest::Approx(0.01 * m.t_contact).epsilon(1e-12));
  CHECK(dem::describe_dem(m).find("no two grains can touch; shortest collision: grains[0] on walls[0]") !=
        std::string::npos);
}

TEST_CASE("materials: a grain's collision with a wall competes for t_c where grains can touch too") {
  // Two Hertz spheres on a rigid floor (E~ doubled, R_eq = 2 r against it): the bounce on the floor
  // is shorter than their collision with each other, whose t_c made run.dt_over_tc's step 41 %
  // longer than the bounce asked. A floor of the scene's law, not rigid, bounces longer than a pair.
  const char* scene = R"(
[scene]
dimension = 3
[domain]
lo = [-0.02, -0.02, 0.0]
hi = [0.02, 0.02, 0.1]
[contact]
model = "hertz"
young_modulus = 1e9
[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
{rigid}
[[grains]]
radius = 0.005
density = 2500
placement = "explicit"
positions = [[0, 0, 0.0052], [0, 0, 0.03]]
[run]
dt_over_tc = 0.01
steps = 10
)";
  const double r = 0.005, mass = 2500 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  auto with = [&](const char* rigid) {
    std::string t = scene;
    t.replace(t.find("{rigid}"), 7, rigid);
    return test::model_from(t);
  };
  const Model m = with("rigid = true");
  const double floor = dem::reference_contact_time(m.wall_contact[0], mass, 2 * r);
  const double pair = dem::reference_contact_time(m.contact, mass / 2, r);
  CHECK(floor < pair / 1.1);
  CHECK(m.t_contact == floor);
  CHECK(m.tc_pair.wall == 0);
  CHECK(dem::describe_dem(m).find("collision reaching contact.hertz_ref_overlap; shortest collision: grains[0] on "
                                  "walls[0], its lightest grain") != std::string::npos);
  const Model plain = with("");
  CHECK(plain.t_contact == doctest::Approx(pair).epsilon(1e-15));
  CHECK(plain.tc_pair.wall == -1);
}

TEST_CASE("materials: springs and masses at the ends of the doubles' range mix without overflow") {
  // 2 k k / (k + k) overflowed for two groups of k_n = 1e200 ("the contacts' stiffness is inf"),
  // where one group of it is accepted; m m / (m + m) for masses of 1e300.
  for (double k : {1e200, 1e-200}) {
    CAPTURE(k);
    std::string s =
        test::fill(kTwoGroups, {{"g", 0.0}, {"rb", 1.0}, {"kb", k}, {"mub", 0.5}, {"ks", k}, {"mus", 0.5}, {"kw", k}});
    s.replace(s.find("dt = 1e-5"), 9, "dt_over_tc = 0.02");
    const Model m = test::model_from(s);
    CHECK(m.pair_contact[0].k0 == doctest::Approx(k).epsilon(1e-12));
    CHECK(m.pair_contact[1].k0 == doctest::Approx(k).epsilon(1e-12));
    CHECK(std::isfinite(m.t_contact));
    CHECK(m.t_contact > 0);
  }
  CHECK(dem::series_stiffness(1e308, 1e308) == 1e308);
  CHECK(dem::series_stiffness(2, 6) == 3);  // 2 * 2 * 6 / 8
}

TEST_CASE("materials: [contact]'s spring or modulus may be left out where every group and wall gives its own") {
  // Two groups of springs of their own and a rigid floor: no contact has [contact]'s k_n.
  const std::string springs = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [1, 1]
[contact]
model = "hooke"
[[walls]]
point = [0, 0]
normal = [0, 1]
{wall}
[[grains]]
radius = 0.05
k_n = 1e4
placement = "explicit"
positions = [[0.3, 0.5]]
[[grains]]
radius = 0.05
{k2}
placement = "explicit"
positions = [[0.7, 0.5]]
[run]
dt = 1e-5
)";
  auto with = [&](const std::string& wall, const std::string& k2) {
    std::string t = springs;
    t.replace(t.find("{wall}"), 6, wall);
    t.replace(t.find("{k2}"), 4, k2);
    return t;
  };
  const Model m = test::model_from(with("rigid = true", "k_n = 3e4"));
  REQUIRE(m.pair_contact.size() == 4);
  CHECK(m.pair_contact[1].k0 == doctest::Approx(1.5e4).epsilon(1e-14));  // 1e4 and 3e4 in series
  CHECK(m.wall_contact[0].k0 == 2e4);                                    // rigid: twice the grain's
  CHECK(m.wall_contact[1].k0 == 6e4);
  // The same scene with [contact]'s k_n given as the first group's: the same laws.
  std::string given = with("rigid = true", "k_n = 3e4");
  given.replace(given.find("model = \"hooke\""), 15, "model = \"hooke\"\nk_n = 1e4");
  const Model same = test::model_from(given);
  CHECK(same.t_contact == m.t_contact);
  CHECK(same.dt_stable == m.dt_stable);
  // Whoever has no spring of its own needs [contact]'s, and is named.
  CHECK(test::scene_error(with("k_n = 5e4", "")) ==
        "bad.toml:7:1: missing required key 'contact.k_n': grains[1] gives no k_n of its own");
  CHECK(test::scene_error(with("", "")) ==
        "bad.toml:7:1: missing required key 'contact.k_n': grains[1], walls[0] give no k_n of their own");
  // A group of no position is refused for that, not for a spring no grain would use.
  std::string empty = with("", "");
  empty.replace(empty.find("positions = [[0.7, 0.5]]"), 24, "positions = []");
  CHECK(test::scene_error(empty).ends_with("no positions given"));
  // Hertz: every group's own modulus (and Poisson ratio); [contact]'s is the first group's material.
  const std::string hertz = R"(
[scene]
dimension = 3
[domain]
lo = [-1, -1, -1]
hi = [1, 1, 1]
[contact]
model = "hertz"
[[grains]]
radius = 1e-3
young_modulus = 7e10
poisson_ratio = 0.2
placement = "explicit"
positions = [[0, 0, 0]]
)";
  const Model h = test::model_from(hertz);
  CHECK(h.contact.e_tilde == doctest::Approx(7e10 / (1 - 0.04)).epsilon(1e-14));
  CHECK(h.pair_contact.empty());  // one material: [contact]'s law itself
}

TEST_CASE("materials: a wall without a friction of its own takes the grain's group's, and check says so") {
  // A group's mu = 0.5 on a wall was taken (a slide decelerated at 0.5 g) while `check` said the
  // scene's 0.05, and the key's text said the wall's default was contact.friction.
  const std::string slide =
      "[scene]\ndimension = 3\n[domain]\nlo = [-1.0, -0.02, 0.0]\nhi = [1.0, 0.02, 0.1]\n[gravity]\nmagnitude = 10.0\n"
      "[contact]\nmodel = \"hooke\"\nk_n = 1000.0\ngamma_n = 2000.0\nfriction = 0.05\n[[walls]]\npoint = [0.0, 0.0, "
      "0.0]\n"
      "normal = [0.0, 0.0, 1.0]\n[[grains]]\nradius = 1e-3\ndensity = 1000.0\nfriction = 0.5\nplacement = "
      "\"explicit\"\n"
      "positions = [[0.0, 0.0, 0.0009999581]]\nvelocity = \"explicit\"\nvelocities = [[1.0, 0.0, 0.0]]\n[run]\ndt = "
      "1e-5\n";
  const Model m = test::model_from(slide);
  REQUIRE(m.wall_contact.size() == 1);
  CHECK(m.wall_contact[0].friction == 0.5);
  CHECK(dem::describe_dem(m).find("mu = 0.05; on the walls mu = 0.5") != std::string::npos);
  // Sliding at 1 m/s on it, the grain slows at mu g = 5 m/s^2 (about 0.2 of the way to rolling).
  Simulation sim(m, 1);
  for (int k = 0; k < 500; ++k) REQUIRE(sim.step());
  CHECK(sim.state().particle_v[0] == doctest::Approx(1 - 5 * 500 * 1e-5).epsilon(1e-3));
  // And a friction that no tangential spring would carry is refused where the spring is given.
  CHECK(test::scene_error(slide) == "");
  std::string no_spring = slide;
  no_spring.replace(no_spring.find("friction = 0.05\n"), 16, "friction = 0.05\nkt_over_kn = 0.0\n");
  CHECK(test::scene_error(no_spring).find("contact.kt_over_kn = 0 leaves no tangential force") != std::string::npos);
}
