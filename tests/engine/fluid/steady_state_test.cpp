// run.stop_when_steady: a run ends when the fluid's velocity changes by less than run.steady_tol
// (relative, per unit time L / U), and what is left to change then is below the tolerance.
#include <doctest/doctest.h>

#include <cmath>

#include "fluid/module.hpp"
#include "fluid/step.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::fluid;

namespace {

// The unit lid-driven cavity at Re = 10 on 16 x 16 cells, for at most 100 L / U.
std::string steady_cavity(const std::string& run) {
  return "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [1.0, 1.0]\n[fluid]\ncells = [16, 16]\n"
         "reynolds = 10.0\n[fluid.boundary]\ny_hi_velocity = [1.0, 0.0]\n[run]\ntime = 100.0\n" +
         run + "\n";
}

std::vector<double> all_velocities(const State& s) {
  std::vector<double> out;
  for (int a = 0; a < 2; ++a) {
    const auto& u = s.module_field(fluid_fields().u[a]);
    out.insert(out.end(), u.begin(), u.end());
  }
  return out;
}

}  // namespace

TEST_CASE("fluid: run.stop_when_steady ends a run when the velocity no longer changes") {
  auto sim = test::simulation_from(steady_cavity("stop_when_steady = true\nsteady_tol = 1e-6"));
  REQUIRE(sim->model().stop_when_steady);
  REQUIRE(has_steady_test(sim->model()));
  RunOptions opt;
  opt.time = 100;
  opt.stop_when_steady = sim->model().stop_when_steady;
  const RunReport rep = sim->run(opt);
  REQUIRE(rep.end == RunEnd::kSteady);
  const double t_stop = sim->state().t;
  INFO("steady at t = " << t_stop << " after " << rep.steps_done << " steps");
  CHECK(t_stop < 50);
  CHECK(sim->state().step % sim->model().limits.check_every == 0);  // tested where the run checks
  const double rate = test::observe(sim->model(), sim->state(), "fluid.change_rate");
  CHECK(rate < 1e-6);
  CHECK(rate > 0);
  CHECK(sim->is_steady());
  // The flow converges as exp(-lambda t), lambda the slowest decay rate of the cavity's modes,
  // about 52 nu / L^2 = 5 U / L at Re = 10 (the first Stokes eigenvalue of a square): what is
  // left to change, relative to the velocity, is the change rate / lambda, below the tolerance.
  const std::vector<double> at_stop = all_velocities(sim->state());
  double speed = 0;
  for (double v : at_stop) speed = std::max(speed, std::abs(v));
  while (sim->state().t < t_stop + 20) REQUIRE(sim->step());
  const double left = test::max_diff(all_velocities(sim->state()), at_stop) / speed;
  INFO("relative change after the stop: " << left);
  CHECK(left < 1e-6);
  CHECK(left > 0);
  // Not stopped much too late either: 100 steps before the stop (the previous test), the change
  // rate was above the tolerance (a run again to there).
  auto again = test::simulation_from(steady_cavity(""));
  RunOptions to_before;
  to_before.steps = rep.steps_done - sim->model().limits.check_every;
  REQUIRE(again->run(to_before).end == RunEnd::kDone);
  CHECK(test::observe(again->model(), again->state(), "fluid.change_rate") >= 1e-6);
  CHECK_FALSE(again->is_steady());
}

TEST_CASE("fluid: a run too short for the steady state ends as its length says, a decaying vortex is never steady") {
  auto sim = test::simulation_from(steady_cavity("stop_when_steady = true"));
  RunOptions opt;
  opt.time = 1.0;
  opt.stop_when_steady = true;
  CHECK(sim->run(opt).end == RunEnd::kDone);
  CHECK(test::observe(sim->model(), sim->state(), "fluid.change_rate") > 1e-6);
  // The Taylor-Green vortex decays at the relative rate 2 nu k^2 = 8 pi^2 / Re per L / U (k = 2 pi
  // / L): 0.79 at Re = 100, which the observable gives to the grid's and step's accuracy.
  auto tg = test::simulation_from(
      "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [1.0, 1.0]\nperiodic = [true, true]\n"
      "[fluid]\ncells = [32, 32]\nreynolds = 100.0\ninitial = \"taylor_green\"\ndt = 0.002\n");
  for (int k = 0; k < 20; ++k) REQUIRE(tg->step());
  const double pi = std::acos(-1.0);
  CHECK(test::observe(tg->model(), tg->state(), "fluid.change_rate") ==
        doctest::Approx(8 * pi * pi / 100).epsilon(0.01));
  CHECK_FALSE(tg->is_steady());
  // A scene without a fluid has no steady-state test.
  CHECK_FALSE(has_steady_test(compile(load_scene_file(test::scene_path("collision_normal")))));
}
