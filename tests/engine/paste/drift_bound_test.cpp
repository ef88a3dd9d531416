// The paste's adaptive step bounded by the drift: after a solve, no grain moves more than
// lubrication.drift_max of its radius (relative to the affine flow) in the next step.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "paste/solve.hpp"
#include "silt/simulation.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// 80 disks compressed dry, dilated by 1.05, then sheared at Vi = 1 under P = 1 on y: the
// velocities relative to the affine flow are of order gammadot a, the adaptive step grows to
// move the grains by a few hundredths of a radius a step.
std::string sheared(const std::string& drift_max) {
  std::string scene = test::paste_disks(
      {.n = 80, .L = 10, .dilation = 1.05, .phi = 0.8, .lubrication = "drift_max = " + drift_max + "\n"});
  scene.replace(scene.find("[box]\npressure = 1.0\n"), 20,
                "[box]\npressure = 1.0\ncontrolled = [false, true]\n[shear]\nviscous_number = 1.0\n");
  return scene;
}

// The largest |V_i| dt / r_i the next step will move a grain by: the state's velocities over the
// step the solve chose (paste_dt).
double next_drift(const State& s) { return paste::fastest_rate(s) * s.module_field(paste::paste_fields().dt)[0]; }

}  // namespace

TEST_CASE("paste: no grain moves more than lubrication.drift_max of its radius in an adaptive step") {
  // Xi is near singular where a few grains held by a chain of connections can roll on each other
  // (a four-bar linkage of lubricated gaps): scenes/paste_shear.toml at Vi = 1 met one at step
  // 885, two disks went at 135 times their neighbours' speed, and the step the adaptive rule had
  // grown from Xi's entries (0.0139, 2 % of strain) moved one into its neighbour by 80 % of its
  // radius. The bound takes the step from the velocities just solved.
  auto free = test::simulation_from(sheared("0"), 1);
  auto bound = test::simulation_from(sheared("0.01"), 1);
  double free_top = 0, bound_top = 0;
  int binding = 0;
  for (int k = 0; k < 60; ++k) {
    REQUIRE(free->step());
    REQUIRE(bound->step());
    free_top = std::max(free_top, next_drift(free->state()));
    const double d = next_drift(bound->state());
    bound_top = std::max(bound_top, d);
    binding += d > 0.01 * (1 - 1e-12);
  }
  // Without the bound the step grows past it; with it, the bound holds at every step and binds.
  CHECK(free_top > 0.01);
  CHECK(bound_top <= 0.01 * (1 + 1e-12));
  CHECK(binding > 0);
  // The quasi-static velocities do not depend on the step: the first state's solve gives the same
  // velocities in both runs, and the first step is bounded too.
  auto a = test::simulation_from(sheared("0"), 1);
  auto b = test::simulation_from(sheared("0.01"), 1);
  a->prepare();
  b->prepare();
  CHECK(a->state().particle_v == b->state().particle_v);
  CHECK(b->state().dt <= a->state().dt);
  CHECK(next_drift(b->state()) <= 0.01 * (1 + 1e-12));
}

TEST_CASE("paste: a drift bound below lubrication.dt_min stops the run naming the drift") {
  // A drift of 1e-9 radius a step wants steps far below dt_min = 1e-6 s.
  std::string scene = sheared("1e-9");
  scene.replace(scene.find("drift_max"), 0, "dt_min = 1e-6\n");
  auto sim = test::simulation_from(scene, 1);
  bool failed = false;
  for (int k = 0; k < 5 && !failed; ++k) failed = !sim->step();
  REQUIRE(failed);
  const StepFailure& f = sim->state().failure;
  CAPTURE(f.message);
  CHECK(f.stage == "lubrication_solve");
  CHECK(f.parameter == "lubrication.dt_min");
  CHECK(f.message.find("lubrication.drift_max = 1e-09 of its radius") != std::string::npos);
  CHECK(std::isfinite(sim->state().particle_x[0]));
}
