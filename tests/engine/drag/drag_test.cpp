// The drag module: Stokes' law through every seam of a module (its key, its fields, its force in
// the kick, its observable, checkpoints and hashes), and the terminal velocity, exact.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// One sphere of radius 1 mm, density 2500, falling from rest in a liquid of viscosity eta.
const char* kFall = R"(
[scene]
dimension = 3
[domain]
lo = [-1, -1, -10]
hi = [1, 1, 1]
[gravity]
vector = [0, 0, -9.81]
[contact]
model = "hooke"
k_n = 1e3
[[grains]]
radius = 1e-3
density = 2500
placement = "explicit"
positions = [[0, 0, 0]]
[drag]
viscosity = {eta}
[run]
dt = {dt}
)";

}  // namespace

TEST_CASE("drag: a sphere reaches Stokes' terminal velocity m g / (6 pi eta r), and its time constant") {
  const double r = 1e-3, m = 2500 * 4.0 / 3.0 * std::numbers::pi * r * r * r, eta = 0.5;
  const double tau = m / (6 * std::numbers::pi * eta * r), vt = 9.81 * tau;
  for (double dt_over_tau : {0.1, 0.01}) {
    CAPTURE(dt_over_tau);
    auto sim = test::simulation_from(test::fill(kFall, {{"eta", eta}, {"dt", dt_over_tau * tau}}));
    const Observer v(sim->model(), {"p[0].vz", "drag.power", "p[0].fz", "p[0].hz"});
    // After one Stokes time: 1 - e^-1 of the terminal velocity, to first order in dt / tau.
    const int64_t n = std::lround(1.0 / dt_over_tau);
    for (int64_t k = 0; k < n; ++k) REQUIRE(sim->step());
    const double after_tau = -v.sample(sim->model(), sim->state())[0];
    CHECK(after_tau == doctest::Approx(vt * (1 - std::exp(-1.0))).epsilon(0.6 * dt_over_tau));
    for (int64_t k = 0; k < 40 * n; ++k) REQUIRE(sim->step());
    const auto x = v.sample(sim->model(), sim->state());
    CHECK(-x[0] == doctest::Approx(vt).epsilon(1e-12));            // the scheme's fixed point is exact
    CHECK(x[1] == doctest::Approx(-m * 9.81 * vt).epsilon(1e-9));  // power: the weight's work, dissipated
    CHECK(std::abs(x[2]) < 1e-9 * m * 9.81);                       // at terminal velocity the net force vanishes
    CHECK(x[3] == doctest::Approx(m * 9.81).epsilon(1e-9));        // the hydrodynamic force holds the weight
  }
}

TEST_CASE("drag: a module that plugs in through its own files") {
  const Model m = test::model_from(test::fill(kFall, {{"eta", 0.5}, {"dt", 1e-5}}));
  CHECK(m.module_on("drag"));
  // Its key in the schema, with its module; its stage in the graph, its force summed by the kick.
  CHECK(find_key_spec("drag.viscosity")->module == "drag");
  auto sim = test::simulation_from(test::fill(kFall, {{"eta", 0.5}, {"dt", 1e-5}}));
  const std::string g = sim->describe_graph();
  CHECK(g.find("drag_forces") != std::string::npos);
  CHECK(g.find("after drag_forces: adds the force of drag_forces") != std::string::npos);
  // Its fields: allocated, hashed, checkpointed.
  for (int k = 0; k < 20; ++k) REQUIRE(sim->step());
  const FieldId f = find_field("particle_f_drag")->id;
  CHECK(double_field(sim->state(), f)[2] > 0);  // it pushes a falling grain up
  write_checkpoint("drag_test.ckpt", sim->model(), sim->state());
  const State back = read_checkpoint("drag_test.ckpt", sim->model());
  CHECK(state_hash(back) == state_hash(sim->state()));
  State other = sim->state();
  double_field(other, f)[0] += 1e-30;
  CHECK(state_hash(other) != state_hash(sim->state()));
  std::remove("drag_test.ckpt");
  // A dry scene has none of it: no stage, no field, no observable.
  const Model dry = compile(load_scene_file(test::scene_path("bounce_dry")));
  CHECK_FALSE(dry.module_on("drag"));
  CHECK(make_state(dry).module_field(f).empty());
  CHECK(check_observable("drag.power", dry).find("drag module") != std::string::npos);
}

TEST_CASE("drag: a time step past the Stokes time is refused at the viscosity") {
  const double r = 1e-3, m = 2500 * 4.0 / 3.0 * std::numbers::pi * r * r * r,
               eta = 20;  // tau = 28 us, under the contacts' stability limit
  const double tau = m / (6 * std::numbers::pi * eta * r);
  const std::string text = test::fill(kFall, {{"eta", eta}, {"dt", 1.5 * tau}});
  const std::string err = test::scene_error(text);
  // Located at the viscosity's line.
  const auto line = std::count(text.begin(), text.begin() + static_cast<long>(text.find("viscosity")), '\n') + 1;
  CHECK(err.find("bad.toml:" + std::to_string(line) + ":") == 0);
  CHECK(err.find("Stokes time") != std::string::npos);
  // The rotation's, I / (8 pi eta r^3) = 0.3 tau for a sphere: half the translation's time was
  // taken, and a spinning grain's spin flipped sign every step.
  const std::string spin = test::scene_error(test::fill(kFall, {{"eta", eta}, {"dt", 0.5 * tau}}));
  CHECK(spin.find("Stokes time of rotation I / (8 pi eta r^3) = ") != std::string::npos);
  CHECK(test::scene_error(test::fill(kFall, {{"eta", eta}, {"dt", 0.25 * tau}})).empty());
}

TEST_CASE("drag: a viscosity steered between steps acts from the next half kick") {
  const double r = 1e-3, m = 2500 * 4.0 / 3.0 * std::numbers::pi * r * r * r, eta = 0.5;
  const double tau = m / (6 * std::numbers::pi * eta * r);
  auto sim = test::simulation_from(test::fill(kFall, {{"eta", eta}, {"dt", 0.01 * tau}}));
  for (int k = 0; k < 20; ++k) REQUIRE(sim->step());
  const FieldId f = find_field("particle_f_drag")->id;
  const double v = sim->state().particle_v[2];
  // The drag the last step left: of the old viscosity, at the half-step velocity.
  REQUIRE(double_field(sim->state(), f)[2] == doctest::Approx(-6 * std::numbers::pi * eta * r * v).epsilon(0.02));
  REQUIRE(sim->steer_stopped(parse_override("drag.viscosity=2")).cannot.empty());
  // Made again under the new one at the state's velocity, in the sum the next half kick uses.
  const double drag = -6 * std::numbers::pi * 2.0 * r * v;
  CHECK(double_field(sim->state(), f)[2] == doctest::Approx(drag).epsilon(1e-14));
  CHECK(sim->state().particle_f[2] == doctest::Approx(drag).epsilon(1e-14));
}
