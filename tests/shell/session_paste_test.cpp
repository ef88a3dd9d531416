// Steering a lubricated paste from the shell while it runs in the background: the roughness, the
// viscous number and the pressure change at a step boundary and the next steps solve with them;
// what would change the system solved is refused until the run stops.
#include <doctest/doctest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

#include "shell/shell_fixtures.hpp"
#include "support/scenes.hpp"

using namespace silt;
using test::contains;
using test::Fixture;

namespace {

// 60 disks at random in a periodic 9 x 9 box, sheared at Vi = 0.1 under P = 1 on y.
const char* kSteeredPaste = R"(
[scene]
dimension = 2
seed = 7
[domain]
lo = [0, 0]
hi = [9, 9]
periodic = [true, true]
[box]
pressure = 1.0
controlled = [false, true]
[shear]
viscous_number = 0.1
[contact]
model = "linear"
k_n = 1e4
friction = 0.3
kt_over_kn = 0.5
[lubrication]
viscosity = 1.0
h_min_over_a = 1e-2
[[grains]]
count = 60
radius_min = 0.35
radius_max = 0.5
placement = "random"
[output]
every = 10
)";

// Writes kSteeredPaste into dir and loads it.
bool load_steered_paste(Fixture& f, const test::TempDir& dir) {
  std::ofstream(dir / "steered_paste.toml") << kSteeredPaste;
  return f.run("load " + (dir / "steered_paste.toml"));
}

// Waits (at most 60 s) until the background run has done `more` steps past `from`.
void wait_for_steps(Fixture& f, double from, double more) {
  const auto t0 = std::chrono::steady_clock::now();
  while (f.value("step") < from + more && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

}  // namespace

TEST_CASE("the shell steers a running paste: h_min, the viscous number and the pressure") {
  test::TempDir dir;
  Fixture f;
  REQUIRE(load_steered_paste(f, dir));
  REQUIRE(f.run("start 1000000"));
  REQUIRE(f.s.running());
  wait_for_steps(f, 0, 5);
  f.take_out();
  REQUIRE(f.run("set lubrication.h_min_over_a 1e-4"));
  CHECK(contains(f.take_out(), "lubrication.h_min_over_a = 1e-4 (from the next step)"));
  REQUIRE(f.run("set shear.viscous_number 0.05"));
  REQUIRE(f.run("set box.pressure 2"));
  CHECK(contains(f.take_out(), "box.pressure = 2 (from the next step)"));
  // What changes the system solved waits for the run to stop.
  CHECK_FALSE(f.run("set lubrication.stepper inertial"));
  CHECK(contains(f.take_err(), "stop first"));
  const double at = f.value("step");
  wait_for_steps(f, at, 20);
  REQUIRE(f.run("stop"));
  CHECK_FALSE(contains(f.take_out(), "failed"));
  CHECK(f.value("step") >= at + 20);
  // The model the steps ran with: the new roughness, Vi = 0.05 at P = 2 (gammadot = Vi P / (eta a)
  // in 2D, a the largest diameter).
  REQUIRE(f.run("check"));
  const std::string model = f.take_out();
  CHECK(contains(model, "h_min/a = 0.0001"));
  CHECK(contains(model, "Vi = eta gammadot a / P = 0.05"));
  CHECK(f.value("gammadot") * test::model_from(kSteeredPaste).a_max == doctest::Approx(0.1));
  CHECK(f.value("Vi") == doctest::Approx(0.05));
  // The box rows held the stress at the new pressure at every solve since (6 digits printed).
  CHECK(f.value("stress.yy") == doctest::Approx(2.0).epsilon(1e-5));
  // Stopped, the stepper can change: the scene is compiled again, the state kept.
  REQUIRE(f.run("set lubrication.stepper inertial"));
  CHECK(contains(f.take_out(), "(state kept)"));
}

TEST_CASE("a change before the first step is made before the setup, bit for bit, and reset starts the cycles again") {
  // load prepared the state (the velocities of the first solve) under the scene's viscosity; a
  // viscosity set before `run` was then solved again from those, to the tolerance only. Now the
  // state goes back to before the setup, which runs under the change: as a simulation steered
  // before it was ever prepared.
  test::TempDir dir;
  const std::string scene = dir / "steered_paste.toml";
  std::ofstream(scene) << kSteeredPaste;
  Simulation direct(compile(load_scene_file(scene)), 1);
  REQUIRE(steer(direct.model_for_steering(), parse_override("lubrication.viscosity=2.5")) == "");
  for (int k = 0; k < 5; ++k) REQUIRE(direct.step());
  char expected[17];
  std::snprintf(expected, sizeof expected, "%016llx", static_cast<unsigned long long>(state_hash(direct.state())));
  Fixture f;
  REQUIRE(f.run("load " + scene));
  REQUIRE(f.run("set lubrication.viscosity 2.5"));
  REQUIRE(f.run("run 5"));
  CHECK(f.hash() == expected);
  // And as the scene compiled with the change (`silt run --set`). The imposed rate Vi P / eta
  // changed with the viscosity, and the first solve took the rate the state was made with.
  Simulation compiled(compile(load_scene_file(scene, {parse_override("lubrication.viscosity=2.5")})), 1);
  for (int k = 0; k < 5; ++k) REQUIRE(compiled.step());
  CHECK(state_hash(compiled.state()) == state_hash(direct.state()));
  // A change the packing's compression depends on is not made to it: the shell says so.
  Fixture p;
  REQUIRE(p.run("load " + test::quarter_paste_scene("paste_iso", dir.path())));
  p.take_out();
  REQUIRE(p.run("set box.pressure 2"));
  CHECK(contains(p.take_out(), "`reset` compresses it again under this value"));
  REQUIRE(p.run("set lubrication.viscosity 2"));
  CHECK_FALSE(contains(p.take_out(), "reset"));
  REQUIRE(p.run("set prepare.dilation 1.2"));  // not live: compiled again, the state kept
  CHECK(contains(p.take_out(), "`reset` compresses it again under this value"));
  // The cycles: a period changed mid-run goes on from the phase reached; reset starts them at 0.
  Fixture c;
  REQUIRE(c.run("load " + test::quarter_paste_scene("paste_cyclic_alternating", dir.path())));
  REQUIRE(c.run("run 20"));
  const double before = c.value("cycle");
  REQUIRE(c.run("set box.cycle_period 1000"));
  CHECK(c.value("cycle") == doctest::Approx(before).epsilon(1e-12));
  REQUIRE(c.run("reset"));
  CHECK(c.value("cycle") == 0);
}

TEST_CASE("a steered value the paste cannot be solved under is refused, and a later good value is taken") {
  // The failed re-solve was left in the state: `set` said the value was set, and every later
  // `run` was refused, even after the value was put back.
  test::TempDir dir;
  Fixture f;
  REQUIRE(load_steered_paste(f, dir));
  REQUIRE(f.run("run 5"));
  // (a pressure of 1e300, which this test set here before, presses the contacts by more than a
  // diameter: refused now, naming the stiffness number)
  CHECK_FALSE(f.run("set box.pressure 1e300"));
  CHECK(contains(f.take_err(), "stiffness number kappa"));
  REQUIRE(f.run("set lubrication.viscosity 1e-300"));
  CHECK_FALSE(f.run("run 3"));  // the step lost in the clock's rounding: back to step 5
  CHECK(f.value("step") == 5);
  const std::string before = f.hash();
  f.take_err();
  // (the state given is solved again under each change from itself: a CG of two iterations cannot)
  REQUIRE(f.run("set lubrication.solver cg"));
  CHECK_FALSE(f.run("set lubrication.max_iterations 2"));
  CHECK(contains(f.take_err(), "set lubrication.max_iterations 2: refused, the state cannot be solved under it"));
  CHECK(f.hash() == before);
  // A viscosity of 1e300, which this test refused here before, is solved: CG starts from zero
  // where the velocities solved under another viscosity are a worse guess, whose round-off
  // swamped the solution (a box rate 1e55 times too large at 1e60).
  REQUIRE(f.run("set lubrication.viscosity 1e300"));
  REQUIRE(f.run("set lubrication.viscosity 1"));
  REQUIRE(f.run("run 2"));
  CHECK(f.value("step") == 7);
  CHECK(f.value("stress.yy") == doctest::Approx(1.0).epsilon(1e-5));
  // So are values set together, which recompile the scene and keep the state: it was installed
  // unsolved, set said nothing, and the next `run` said "the last run failed" (the run had
  // succeeded).
  const std::string kept = f.hash();
  f.take_out();
  CHECK_FALSE(f.run("set lubrication.h_min_over_a 2e-2 lubrication.max_iterations 2"));
  CHECK(contains(f.take_err(), "lubrication.max_iterations 2: refused, the state cannot be solved under it (step 8"));
  CHECK(f.hash() == kept);
  REQUIRE(f.run("get lubrication.h_min_over_a"));
  const std::string h_min = f.take_out();
  CAPTURE(h_min);
  CHECK(contains(h_min, "lubrication.h_min_over_a = 0.01"));
  REQUIRE(f.run("run 2"));
  CHECK(f.value("step") == 9);
}

TEST_CASE("a key that is not live, set and set back after a restore, gives the checkpoint again bit for bit") {
  // The recompile carried the state solved under the other value, which was then solved again
  // under the first value from there: another hash (the live keys already came back to it).
  test::TempDir dir;
  const std::string ckpt = dir / "steered_paste.ckpt";
  Fixture f;
  REQUIRE(load_steered_paste(f, dir));
  REQUIRE(f.run("run 5"));
  REQUIRE(f.run("save " + ckpt));
  REQUIRE(f.run("restore " + ckpt));
  const std::string given = f.hash();
  REQUIRE(f.run("set lubrication.h_max_over_a 0.6"));
  CHECK(f.hash() != given);
  REQUIRE(f.run("restore " + ckpt));
  REQUIRE(f.run("set lubrication.h_max_over_a 0.5"));
  CHECK(f.hash() == given);
}

TEST_CASE("a paste's fixed step set in the shell replaces the adaptive step's keys, and they replace it") {
  // lubrication.dt beside drift_max was taken, and drift_max did nothing; now the two are
  // alternatives: a set of one removes the other, as fluid.dt and fluid.cfl.
  test::TempDir dir;
  Fixture f;
  REQUIRE(load_steered_paste(f, dir));
  REQUIRE(f.run("set lubrication.drift_max 0.1"));
  REQUIRE(f.run("set lubrication.dt_max 0.5"));
  REQUIRE(f.run("run 3"));
  f.take_out();
  REQUIRE(f.run("set lubrication.dt 0.002"));
  CHECK(contains(f.take_out(),
                 "note: lubrication.dt replaces lubrication.dt_max, lubrication.drift_max, alternatives given before"));
  REQUIRE(f.run("get lubrication.drift_max"));
  CHECK(contains(f.take_out(), "lubrication.drift_max = 0.05 (default)"));
  REQUIRE(f.run("get lubrication.dt_max"));
  CHECK(contains(f.take_out(), "(not set)"));
  REQUIRE(f.run("check"));
  CHECK(contains(f.take_out(), "time step fixed at 0.002"));
  const double t = f.value("t");
  REQUIRE(f.run("run 2"));
  CHECK(f.value("t") == doctest::Approx(t + 0.004).epsilon(1e-12));
  REQUIRE(f.run("set lubrication.drift_max 0.1"));
  CHECK(contains(f.take_out(), "note: lubrication.drift_max replaces lubrication.dt, an alternative given before"));
  REQUIRE(f.run("get lubrication.dt"));
  CHECK(contains(f.take_out(), "(not set)"));
  REQUIRE(f.run("check"));
  CHECK(contains(f.take_out(), "time step adaptive"));
  // A scene's own adaptive key, replaced by lubrication.dt, comes back when it goes: said.
  std::string own = kSteeredPaste;
  own.replace(own.find("h_min_over_a = 1e-2\n"), 20, "h_min_over_a = 1e-2\ndt_max = 0.5\n");
  std::ofstream(dir / "own_step.toml") << own;
  REQUIRE(f.run("load " + (dir / "own_step.toml")));
  REQUIRE(f.run("set lubrication.dt 0.002"));
  CHECK(contains(f.take_out(), "note: lubrication.dt replaces lubrication.dt_max, an alternative given before"));
  REQUIRE(f.run("set lubrication.dt_growth 1.3"));
  const std::string out = f.take_out();
  CHECK(contains(out, "note: lubrication.dt_growth replaces lubrication.dt, an alternative given before"));
  CHECK(contains(out, "note: the scene's lubrication.dt_max applies again"));
}
