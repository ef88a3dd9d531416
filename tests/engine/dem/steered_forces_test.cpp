// A value the forces depend on, steered between steps: the forces are made again before the next
// half kick uses them (dem/forces_under.hpp), whether it is steered in place or the state is given
// to a model compiled with it; set and set back, it changes nothing.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "dem/stress.hpp"
#include "silt/simulation.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// 60 frictional disks poured on a floor under a gravity tilted 25 degrees, periodic along x: many
// contacts then carry a tangential force well above 0.05 of their normal one.
const char* kPile = R"(
[scene]
dimension = 2
seed = 3
[domain]
lo = [0, 0]
hi = [10, 8]
periodic = [true, false]
[gravity]
magnitude = 9.81
angle = 25
[contact]
model = "hooke"
k_n = 2e5
gamma_n = 50
friction = {mu}
[[walls]]
point = [0, 0]
normal = [0, 1]
friction = 0.5
[[grains]]
count = 60
radius_min = 0.4
radius_max = 0.5
placement = "random"
[run]
dt = 1e-4
)";

std::string pile(double mu) { return test::fill(kPile, {{"mu", mu}}); }

// The largest |f_t| / |f_n| over the touching pairs of the state's list (pair_f: on i from j).
double largest_mobilisation(const State& s) {
  double worst = 0;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      if (!s.pair_touch[p]) continue;
      const int64_t j = s.pair_j[p];
      double d[3] = {0, 0, 0}, f[2] = {s.pair_f[2 * p], s.pair_f[2 * p + 1]};
      for (int c = 0; c < 2; ++c) d[c] = s.particle_x[2 * i + c] - s.particle_x[2 * j + c];
      s.box.nearest(d, 2);
      const double len = std::hypot(d[0], d[1]);
      const double fn = (f[0] * d[0] + f[1] * d[1]) / len;
      const double ft = std::abs(f[0] * d[1] - f[1] * d[0]) / len;
      if (std::abs(fn) > 0) worst = std::max(worst, ft / std::abs(fn));
    }
  return worst;
}

std::unique_ptr<Simulation> poured(int steps) {
  auto sim = test::simulation_from(pile(0.5));
  for (int k = 0; k < steps; ++k) REQUIRE(sim->step());
  return sim;
}

}  // namespace

TEST_CASE("a friction steered between steps: the forces of the state are made under it at once") {
  auto sim = poured(6000);
  // Contacts mobilised beyond the new coefficient: the change must clip them.
  REQUIRE(largest_mobilisation(sim->state()) > 0.2);
  const auto outcome = sim->steer_stopped(parse_override("contact.friction=0.05"));
  REQUIRE(outcome.cannot.empty());
  REQUIRE(outcome.refused.empty());
  // Coulomb's bound of the new coefficient on every contact (the rounding of the clip's scaling).
  CHECK(largest_mobilisation(sim->state()) <= 0.05 * (1 + 1e-12));
  CHECK(largest_mobilisation(sim->state()) > 0.049);

  // The same state given to the scene compiled with the new coefficient: the same forces, and the
  // same steps after them, to the bit.
  auto fresh = poured(6000);
  auto compiled = test::simulation_from(pile(0.05));
  compiled->restore(fresh->state());
  compiled->prepare();
  CHECK(state_hash(compiled->state()) == state_hash(sim->state()));
  for (int k = 0; k < 200; ++k) {
    REQUIRE(sim->step());
    REQUIRE(compiled->step());
  }
  CHECK(state_hash(compiled->state()) == state_hash(sim->state()));
}

TEST_CASE("a friction steered while running enters the next step, and one set and set back changes nothing") {
  // Between two steps of a run (the shell's `set` while it runs), after 99 of them: the next step
  // moves the grains with the forces of the new coefficient, as the state given to the scene
  // compiled with it does.
  auto steered = poured(6000);
  RunOptions opt;
  opt.steps = 300;
  int calls = 0;
  opt.boundary_wanted = [] { return true; };
  opt.between_steps = [&] {
    if (++calls == 100) REQUIRE(steer(steered->model_for_steering(), parse_override("contact.friction=0.05")).empty());
  };
  REQUIRE(steered->run(opt).end == RunEnd::kDone);
  auto at = poured(6000);
  RunOptions first;
  first.steps = 99;
  REQUIRE(at->run(first).end == RunEnd::kDone);
  auto compiled = test::simulation_from(pile(0.05));
  compiled->restore(at->state());
  RunOptions rest;
  rest.steps = 201;
  REQUIRE(compiled->run(rest).end == RunEnd::kDone);
  CHECK(state_hash(compiled->state()) == state_hash(steered->state()));
  // Not the run that changed nothing.
  REQUIRE(at->run(rest).end == RunEnd::kDone);
  CHECK(state_hash(at->state()) != state_hash(steered->state()));

  // Set and set back before the next step: the forces the last step left come back.
  opt.between_steps = nullptr;
  auto again = poured(6000);
  REQUIRE(again->steer_stopped(parse_override("contact.friction=0.1")).cannot.empty());
  REQUIRE(again->steer_stopped(parse_override("contact.friction=0.5")).cannot.empty());
  REQUIRE(again->run(opt).end == RunEnd::kDone);
  auto reference = poured(6000);
  REQUIRE(reference->run(opt).end == RunEnd::kDone);
  CHECK(state_hash(again->state()) == state_hash(reference->state()));
}

TEST_CASE(
    "a friction steered under a stress-controlled box: the box's next half kick uses the stresses of the new forces") {
  // procedure O's compression of 224 disks, 5,000 steps in: its contacts slide and stick.
  auto sim = std::make_unique<Simulation>(compile(load_scene_file(test::scene_path("pack_2d"))), 1);
  for (int k = 0; k < 5000; ++k) REQUIRE(sim->step());
  REQUIRE(largest_mobilisation(sim->state()) > 0.1);
  const Vec3a before = sim->state().box_stress;
  REQUIRE(sim->steer_stopped(parse_override("contact.friction=0.02")).cannot.empty());
  CHECK(largest_mobilisation(sim->state()) <= 0.02 * (1 + 1e-12));
  // The contact stress of the clipped forces (their virial, pair by pair).
  const Vec3a after = sim->state().box_stress;
  CHECK((after[0] != before[0] || after[1] != before[1]));
  const std::array<double, 9> virial = dem::virial_sums<false>(sim->state());
  const double area = sim->state().box.len[0] * sim->state().box.len[1];
  CHECK(after[0] == doctest::Approx(virial[0] / area).epsilon(1e-14));
  CHECK(after[1] == doctest::Approx(virial[4] / area).epsilon(1e-14));
}

TEST_CASE("a state given under other parameters: a listed pair left out of the contact candidates holds no spring") {
  // A pair that cannot touch but holds a spring and a force (a state made by hand, or a checkpoint
  // altered): the candidates, chosen before the forces are made again, clear all three, as a step
  // would. They were chosen inside the pair loop, after the springs were kept, and the spring came
  // back without its contact.
  auto fresh = poured(6000);
  State s = fresh->state();
  const Model& m = fresh->model();
  REQUIRE(m.contact_skin < m.skin);
  int64_t left_out = -1;
  for (int64_t i = 0; i < s.n && left_out < 0; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      const int64_t j = s.pair_j[p];
      double d[3] = {s.particle_x[2 * i] - s.particle_x[2 * j], s.particle_x[2 * i + 1] - s.particle_x[2 * j + 1], 0};
      s.box.nearest(d, 2);
      if (std::hypot(d[0], d[1]) - s.particle_r[i] - s.particle_r[j] > 2 * m.contact_skin) {
        left_out = p;
        break;
      }
    }
  REQUIRE(left_out >= 0);
  s.pair_touch[left_out] = 1;
  s.pair_hist[2 * left_out] = 1e-3;
  s.pair_f[2 * left_out] = 5.0;
  auto compiled = test::simulation_from(pile(0.05));
  compiled->restore(s);
  compiled->prepare();
  const State& made = compiled->state();
  CHECK(made.pair_touch[left_out] == 0);
  CHECK(made.pair_hist[2 * left_out] == 0.0);
  CHECK(made.pair_hist[2 * left_out + 1] == 0.0);
  CHECK(made.pair_f[2 * left_out] == 0.0);
}
