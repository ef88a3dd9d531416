// Stress-controlled box (Peyneau 2009 eq. 3.11): sign convention and relaxation to the pressure.
#include <doctest/doctest.h>

#include "silt/observables.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

const char* kDisks = R"(
[scene]
dimension = 2
seed = 9
[domain]
lo = [0, 0]
hi = [{L}, {L}]
periodic = [true, true]
[box]
pressure = 1.0
[contact]
model = "linear"
k_n = 1e3
damping = 0.7
friction = 0.0
[[grains]]
count = 120
radius_min = 0.35
radius_max = 0.5
placement = "random"
[run]
dt_over_tc = 0.05
stop_when_static = true
static_force_tol = 1e-3
static_stress_tol = 1e-3
static_ke_tol = 1e-8
)";

}  // namespace

TEST_CASE("a granular gas below the imposed pressure makes the box shrink, then holds it at P") {
  auto sim = test::simulation_from(test::fill(kDisks, {{"L", 13.0}}), 2);
  const double L0 = sim->state().box.len[0];
  for (int k = 0; k < 200; ++k) REQUIRE(sim->step());
  CHECK(sim->state().box.len[0] < L0);  // contact pressure 0 < P: the box contracts
  CHECK(sim->state().box.len[1] < L0);
  RunOptions opt;
  opt.steps = 2'000'000;
  opt.stop_when_static = true;
  const RunReport r = sim->run(opt);
  REQUIRE(r.end == RunEnd::kStatic);
  const Measurements m = measure(sim->model(), sim->state());
  CHECK(m.stress[0][0] == doctest::Approx(1.0).epsilon(1e-3));
  CHECK(m.stress[1][1] == doctest::Approx(1.0).epsilon(1e-3));
  CHECK(m.phi > 0.8);  // a static frictionless 2D packing near random close packing
  CHECK(m.phi < 0.87);
  CHECK(m.z_star > 3.6);  // isostatic 4 for rigid frictionless disks, slightly below at finite stiffness
}

TEST_CASE("a packing squeezed above the pressure makes the box expand") {
  auto sim = test::simulation_from(test::fill(kDisks, {{"L", 13.0}}), 1);
  RunOptions opt;
  opt.steps = 2'000'000;
  opt.stop_when_static = true;
  REQUIRE(sim->run(opt).end == RunEnd::kStatic);
  sim->model_for_steering().box_control.pressure = 0.5;  // lower target: now sigma > P
  const double L = sim->state().box.len[0];
  for (int k = 0; k < 100; ++k) REQUIRE(sim->step());
  CHECK(sim->state().box.len[0] > L);
}
