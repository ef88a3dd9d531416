// What a paste tells the user while it runs: the grains with no lubricated connection, named once
// each time their set changes (held at the affine flow, a documented choice), and a solve that
// does not converge, reported with its step, its residual and the key to change.
#include <doctest/doctest.h>

#include <algorithm>

#include <cmath>
#include <set>
#include <string>

#include "paste/params.hpp"
#include "paste/solve.hpp"
#include "silt/text.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// Disks of radius 0.5 (a = 1, h_max = 0.5) sheared at gammadot = 1 in a fixed periodic 12 x 12
// box: 0, 1 and 2 in a cluster; 3 far above it, alone for good; 4 just below and to the right of
// grain 1 (gap 0.8), alone at first, then carried toward it by the shear (0.4 slower along x).
const char* kLonelyPaste = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [12, 12]
periodic = [true, true]
[shear]
rate = 1.0
[contact]
model = "linear"
k_n = 1e4
[lubrication]
viscosity = 1.0
h_min_over_a = 1e-2
{extra}
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[3.0, 6.0], [4.05, 6.0], [3.5, 6.9], [9.0, 9.5], [5.8, 5.6]]
)";

std::string lonely_scene(const std::string& extra = "") {
  std::string s = kLonelyPaste;
  s.replace(s.find("{extra}"), 7, extra);
  return s;
}

// 60 disks placed at random in a periodic 9 x 9 box under a pressure P = 1: a loose paste.
std::string loose_scene(const std::string& extra) { return test::paste_disks({.lubrication = extra}); }

// The ids of the grains farther than h_max from every other (their nearest images), from the
// positions alone.
std::set<int> alone_by_geometry(const State& s, double h_max) {
  std::set<int> out;
  for (int64_t i = 0; i < s.n; ++i) {
    bool connected = false;
    for (int64_t j = 0; j < s.n && !connected; ++j) {
      if (j == i) continue;
      double d[3] = {0, 0, 0}, dist2 = 0;
      for (int a = 0; a < s.dim; ++a) d[a] = s.particle_x[s.dim * j + a] - s.particle_x[s.dim * i + a];
      s.box.nearest(d, s.dim);
      for (int a = 0; a < s.dim; ++a) dist2 += d[a] * d[a];
      connected = std::sqrt(dist2) - s.particle_r[i] - s.particle_r[j] <= h_max;
    }
    if (!connected) out.insert(s.particle_id[i]);
  }
  return out;
}

// The note a run gives for this set at this step.
std::string expected_note(int64_t step, const std::set<int>& ids) {
  std::string list;
  for (int id : ids) list += (list.empty() ? "" : ", ") + std::to_string(id);
  if (ids.empty()) return "step " + std::to_string(step) + ": every grain has a lubricated connection again";
  return "step " + std::to_string(step) + ": " + (ids.size() == 1 ? "grain " : "grains ") + list +
         (ids.size() == 1 ? " has" : " have") + " no lubricated connection";
}

}  // namespace

TEST_CASE("paste: grains with no lubricated connection are named once each time their set changes") {
  auto sim = test::simulation_from(lonely_scene(), 1);
  const double h_max = 0.5;
  sim->prepare();
  std::vector<std::string> notes = sim->take_notices();
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].rfind(expected_note(0, {3, 4}), 0) == 0);
  CHECK(notes[0].find("held at the affine flow") != std::string::npos);
  CHECK(notes[0].find("lubrication.stokes_drag") != std::string::npos);
  // The grains alone are held at the affine flow: no velocity relative to it.
  for (int a = 0; a < 2; ++a) CHECK(sim->state().particle_v[2 * 3 + a] == 0);
  std::set<int> before = alone_by_geometry(sim->state(), h_max);
  REQUIRE(before == std::set<int>{3, 4});
  int changes = 0;
  for (int k = 0; k < 400 && changes < 2; ++k) {
    REQUIRE(sim->step());
    const State& s = sim->state();
    const std::set<int> now = alone_by_geometry(s, h_max);
    notes = sim->take_notices();
    CAPTURE(s.step);
    if (now == before) {
      CHECK(notes.empty());
      continue;
    }
    ++changes;
    REQUIRE(notes.size() == 1);
    CHECK(notes[0].rfind(expected_note(s.step, now), 0) == 0);
    before = now;
  }
  // Grain 4 reached grain 1 (only 3 left alone), then left it again or stayed: at least one
  // change was seen, the first of them grain 4 joining.
  CHECK(changes >= 1);
  CHECK(before.count(3) == 1);
}

TEST_CASE("paste: with a Stokes drag or inertia no grain is held, and none is named") {
  for (const std::string extra : {"stokes_drag = true", "stepper = \"inertial\"\ndt = 1e-3"}) {
    CAPTURE(extra);
    auto sim = test::simulation_from(lonely_scene(extra), 1);
    sim->prepare();
    for (int k = 0; k < 3; ++k) REQUIRE(sim->step());
    CHECK(sim->take_notices().empty());
  }
}

TEST_CASE("paste: a solve that does not converge stops the run naming the step, the residual and the key") {
  // Jacobi CG allowed 3 iterations on a loose paste under pressure: far from the tolerance.
  auto sim = test::simulation_from(loose_scene("solver = \"cg\"\nmax_iterations = 3"), 1);
  CHECK_FALSE(sim->step());
  const StepFailure& f = sim->state().failure;
  CHECK(f.step == 1);
  CHECK(f.stage == "lubrication_solve");
  CHECK(f.parameter == "lubrication.max_iterations");
  const auto& stats = sim->state().module_field(paste::paste_fields().solver);
  REQUIRE(stats.size() == paste::kSolverStats);
  CHECK(stats[paste::kLastIterations] == 3);
  const double residual = stats[paste::kLastResidual];
  CHECK(residual > 1e-8);  // above lubrication.tolerance
  CHECK(std::isfinite(residual));
  CAPTURE(f.message);
  CHECK(f.message.rfind("step 1, stage lubrication_solve: the lubrication solve did not converge", 0) == 0);
  CHECK(f.message.find("relative residual " + format_number(residual, 4) + " after 3 iterations") != std::string::npos);
  CHECK(f.message.find("above lubrication.tolerance = " + format_number(1e-8, 4)) != std::string::npos);
  CHECK(f.message.find("raise lubrication.max_iterations") != std::string::npos);
  // The last good state is the first one, whole.
  const State good = sim->last_good_state();
  CHECK(good.step == 0);
  for (double v : good.particle_v) CHECK(std::isfinite(v));
  // A tolerance below round-off is refused up front (1e-16 ran until max_iterations, which the
  // failure then named).
  CHECK(test::scene_error(loose_scene("tolerance = 1e-16")).find("out of range [1e-15") != std::string::npos);
}

TEST_CASE("paste: grains too light for the inertial stepper's matrix stop the run naming the stepper") {
  // At a density of 1e-100 the masses M / dt are 1e-100 of Xi: the matrix M / dt + Xi cannot
  // resolve the grains' common translations in double precision. The first state's solve failed,
  // its failure was dropped, and the first step moved the box through zero (a box length of
  // -1.9e42 named as the failure, with "use more grains or a lower box.pressure").
  const auto light = [](double rho) {
    return test::paste_disks({.density = rho, .lubrication = "stepper = \"inertial\"\n"});
  };
  auto sim = test::simulation_from(light(1e-100), 1);
  const State first = sim->state();
  CHECK_FALSE(sim->step());
  const StepFailure& f = sim->state().failure;
  CAPTURE(f.message);
  CHECK(f.step == 1);
  CHECK(f.stage == "lubrication_solve");
  CHECK(f.parameter == "lubrication.stepper");
  CHECK(f.message.find("cannot resolve the grains' common translations") != std::string::npos);
  CHECK(f.message.find("lubrication.stepper = \"quasi_static\"") != std::string::npos);
  // The last good state is the one given, before the first state's solve.
  const State good = sim->last_good_state();
  CHECK(good.step == 0);
  CHECK(good.particle_x == first.particle_x);
  CHECK(good.box.len == first.box.len);
  // Grains of a millionth of the density are solved and stepped.
  auto heavier = test::simulation_from(light(1e-6), 1);
  for (int k = 0; k < 3; ++k) CHECK(heavier->step());
}

TEST_CASE("paste: a viscosity whose resistances overflow is named, not the loads") {
  // At 1e306 Pa s xi_N at h_min reaches 1.2e308 N s/m: the solve met infinities and the report
  // advised lowering the loads (a pressure of 1 Pa). 1e300 runs.
  for (double eta : {1e306, 1e308}) {
    CAPTURE(eta);
    auto sim = test::simulation_from(test::paste_disks({.viscosity = eta}), 1);
    CHECK_FALSE(sim->step());
    const StepFailure& f = sim->state().failure;
    CAPTURE(f.message);
    CHECK(f.step == 1);
    CHECK(f.parameter == "lubrication.viscosity");
    CHECK(f.message.find("the lubrication resistances overflow") != std::string::npos);
  }
  auto fine = test::simulation_from(test::paste_disks({.viscosity = 1e300}), 1);
  CHECK(fine->step());
}

TEST_CASE("paste: a step that moves the grains into each other names the paste's step key, not run.dt") {
  // The loose paste with a step of 100 eta / P: its grains pass through each other. The DEM's
  // inertial limit does not apply to solved velocities; the key to lower is the paste's.
  for (const auto& c : {std::pair<std::string, std::string>{"dt = 100.0", "lubrication.dt"},
                        {"dt_initial = 100.0\ndt_max = 1000.0\ndrift_max = 0.0", "lubrication.dt_max"}}) {
    const std::string& extra = c.first;  // (not a structured binding: clang's CAPTURE cannot take one)
    const std::string& key = c.second;
    CAPTURE(extra);
    auto sim = test::simulation_from(loose_scene(extra), 1);
    bool failed = false;
    for (int k = 0; k < 5 && !failed; ++k) failed = !sim->step();
    REQUIRE(failed);
    const StepFailure& f = sim->state().failure;
    CAPTURE(f.message);
    CHECK(f.parameter == key);
    CHECK(f.message.find("moved the grains into each other; lower " + key) != std::string::npos);
  }
  // With the drift bounded (the default), the same steps of 100 eta / P move no grain by more
  // than 5 % of its radius: no overlap in 100 steps, even at a bound of a whole radius; an overlap
  // would be reported at the bound.
  for (const char* bound : {"", "\ndrift_max = 1.0"}) {
    auto bounded = test::simulation_from(loose_scene(std::string("dt_initial = 100.0\ndt_max = 1000.0") + bound), 1);
    CHECK(bounded->model().drift_key == "lubrication.drift_max");
    for (int k = 0; k < 100; ++k) REQUIRE(bounded->step());
  }
  // The same step steered (the shell's `set lubrication.dt 100`): it named lubrication.dt_max,
  // which a fixed step then refuses.
  auto sim = test::simulation_from(loose_scene(""), 1);
  REQUIRE(sim->step());
  REQUIRE(steer(sim->model_for_steering(), parse_override("lubrication.dt=100.0")) == "");
  bool failed = false;
  for (int k = 0; k < 5 && !failed; ++k) failed = !sim->step();
  REQUIRE(failed);
  CHECK(sim->state().failure.parameter == "lubrication.dt");
}

TEST_CASE("paste: an overlap under a pressure the contacts are too soft for names their stiffness") {
  // A paste given box.pressure = 1e3 on k_n = 1e4 (kappa = 10: a contact deflects by about 20 % of
  // a radius at the mean force) failed on an overlap advising a lower drift_max, under which it
  // failed the same way; a fresh run of it fails in its dry compression naming contact.k_n.
  auto sim = test::simulation_from(loose_scene(""), 1);
  for (int k = 0; k < 5; ++k) REQUIRE(sim->step());
  std::string soft = loose_scene("");
  soft.replace(soft.find("pressure = 1.0"), 14, "pressure = 1e3");
  auto pressed = test::simulation_from(soft, 1);
  pressed->restore(sim->state());
  bool failed = false;
  for (int k = 0; k < 2000 && !failed; ++k) failed = !pressed->step();
  REQUIRE(failed);
  const StepFailure& f = pressed->state().failure;
  CAPTURE(f.message);
  CHECK(f.parameter == "contact.k_n");
  CHECK(f.message.find("the contacts are too soft for box.pressure = 1000") != std::string::npos);
  CHECK(f.message.find("(stiffness number kappa = 10:") != std::string::npos);
}

TEST_CASE("paste: a solve again under a steered viscosity that does not converge names lubrication_resolve") {
  // It was reported as lubrication_solve, a stage that had not run yet in that step.
  auto sim = test::simulation_from(loose_scene("solver = \"cg\""), 1);
  for (int k = 0; k < 2; ++k) REQUIRE(sim->step());
  Model& m = sim->model_for_steering();
  REQUIRE(steer(m, parse_override("lubrication.viscosity=2.0")) == "");
  REQUIRE(steer(m, parse_override("lubrication.max_iterations=2")) == "");
  CHECK_FALSE(sim->step());
  const StepFailure& f = sim->state().failure;
  CHECK(f.step == 3);
  CHECK(f.stage == "lubrication_resolve");
  CHECK(f.parameter == "lubrication.max_iterations");
  CAPTURE(f.message);
  CHECK(f.message.rfind("step 3, stage lubrication_resolve: the lubrication solve did not converge", 0) == 0);
  CHECK(sim->last_good_state().step == 2);
}

TEST_CASE("paste: a change steered while stopped that the state cannot be solved under is refused, all as it was") {
  // The shell's `set` and a sweep's next point. A steered viscosity is solved again by the next
  // step (which fails here, its solve held to 2 iterations); the next change is tried from the last
  // good state, solved again at once, and refused with the model and the state as they were,
  // rather than leaving a state no run can leave.
  auto sim = test::simulation_from(loose_scene("solver = \"cg\""), 1);
  for (int k = 0; k < 2; ++k) REQUIRE(sim->step());
  Simulation::SteerOutcome o = sim->steer_stopped(parse_override("lubrication.max_iterations=2"));
  REQUIRE((o.cannot.empty() && o.refused.empty()));
  const uint64_t good = state_hash(sim->state());
  o = sim->steer_stopped(parse_override("lubrication.viscosity=2.0"));
  REQUIRE((o.cannot.empty() && o.refused.empty()));
  CHECK_FALSE(sim->step());
  CHECK(sim->state().failure.stage == "lubrication_resolve");
  o = sim->steer_stopped(parse_override("lubrication.viscosity=3.0"));
  CHECK(o.cannot.empty());
  CAPTURE(o.refused);
  CHECK(o.refused.find("did not converge") != std::string::npos);
  CHECK(state_hash(sim->state()) == good);
  CHECK_FALSE(sim->state().failure.failed);
  // With the solve's iterations back, the run goes on.
  o = sim->steer_stopped(parse_override("lubrication.max_iterations=1000"));
  CHECK((o.cannot.empty() && o.refused.empty()));
  REQUIRE(sim->step());
  CHECK(sim->state().step == 3);
  // A key a running model cannot take is said, for the caller to compile the scene again.
  CHECK_FALSE(sim->steer_stopped(parse_override("shear.viscous_number=0.1")).cannot.empty());
  // After a first step that failed, the state steered from is the scene's, not one given (which a
  // change of the scene would keep rather than make again).
  auto fresh = test::simulation_from(loose_scene("solver = \"cg\"\nmax_iterations = 3"), 1);
  CHECK_FALSE(fresh->step());
  o = fresh->steer_stopped(parse_override("lubrication.max_iterations=1000"));
  CHECK((o.cannot.empty() && o.refused.empty()));
  CHECK(fresh->state().step == 0);
  CHECK_FALSE(fresh->state_given());
  CHECK(fresh->step());
}

TEST_CASE("paste: a solve that overflows names the loads by their values") {
  // Vi = 1e200 makes gammadot 1e200 / (eta a / P): the forces overflow in the first solve, whose
  // message said "lower the loads" without saying which.
  auto sim = test::simulation_from(test::paste_disks({}) + "[shear]\nviscous_number = 1e200\n", 1);
  CHECK_FALSE(sim->step());
  const StepFailure& f = sim->state().failure;
  INFO(f.message);
  CHECK(f.message.find("overflowed") != std::string::npos);
  CHECK(f.message.find("(the shear rate 1.008e+200 1/s, the pressure 1 Pa)") != std::string::npos);  // eta a = 0.992
}

TEST_CASE("paste: the state before the first step shows the paste's first step, not the contacts' dt") {
  auto sim = test::simulation_from(loose_scene(""), 1);
  const double dem_dt = sim->state().dt;
  sim->prepare();
  const auto& p = sim->model().params.get<paste::PasteParams>();
  CHECK(p.dt_initial != dem_dt);
  // dt_initial, or shorter where the first state's velocities would move a grain farther than
  // drift_max of its radius in it (this loose paste's do, by 0.6 %).
  const State& s = sim->state();
  const double first = std::min(p.dt_initial, p.drift_max / paste::fastest_rate(s));
  CHECK(first < p.dt_initial);
  CHECK(s.dt == first);
  REQUIRE(sim->step());
  CHECK(sim->state().t == doctest::Approx(first).epsilon(1e-15));  // the step it showed
}

// An error more than one key could have caused is reported at a key the scene gives: the step
// bounds at the first of dt_initial, dt_max, dt_min given; gravity at its own key.
TEST_CASE("paste: a refused step bound or gravity is reported at the key given") {
  auto line_of = [](const std::string& text, const std::string& key) {
    const size_t at = text.find(key);
    return "bad.toml:" + std::to_string(1 + std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + ":";
  };
  // A first step above the default largest (0.01 of 1 / gammadot): at dt_initial, the one given.
  const std::string high_first = lonely_scene("dt_initial = 0.1");
  const std::string e1 = test::scene_error(high_first);
  CHECK(e1.rfind(line_of(high_first, "dt_initial"), 0) == 0);
  CHECK(e1.find("dt_min <= dt_initial <= dt_max") != std::string::npos);
  // dt_min above dt_max (the first step defaults to dt_max): at dt_max.
  const std::string crossed = lonely_scene("dt_min = 1e-3\ndt_max = 1e-4");
  CHECK(test::scene_error(crossed).rfind(line_of(crossed, "dt_max"), 0) == 0);
  // All three given: at dt_initial.
  const std::string three = lonely_scene("dt_min = 1e-3\ndt_max = 1e-2\ndt_initial = 1e-4");
  CHECK(test::scene_error(three).rfind(line_of(three, "dt_initial"), 0) == 0);
  // Gravity on a paste: at the gravity key, not at [lubrication].
  std::string heavy = lonely_scene();
  heavy.replace(heavy.find("[[grains]]"), 10, "[gravity]\nvector = [0.0, -1.0]\n[[grains]]");
  const std::string e3 = test::scene_error(heavy);
  CHECK(e3.rfind(line_of(heavy, "vector ="), 0) == 0);
  CHECK(e3.find("a paste has no gravity") != std::string::npos);
}

TEST_CASE(
    "paste: a fixed step is described as fixed, and refuses the adaptive step's keys and a step below its floor") {
  // `silt check` said "(adaptive time step)" of a fixed lubrication.dt; dt_growth, dt_change and
  // drift_max were taken beside it and did nothing; a step of 1e-20 of the viscous time was taken.
  const auto run_line = [](const std::string& lubrication) {
    std::string scene = loose_scene(lubrication);
    scene.replace(scene.find("[run]\n"), 6, "[run]\nsteps = 10\n");
    const std::string text = describe(test::simulation_from(scene, 1)->model());
    return text.substr(text.find("\nrun "));
  };
  CHECK(run_line("dt = 0.01\n").find("10 steps (fixed time step 0.01 s)") != std::string::npos);
  CHECK(run_line("").find("10 steps (adaptive time step: the first 0.00099") != std::string::npos);
  for (const char* key : {"dt_growth = 1.3", "dt_change = 0.1", "drift_max = 0.1"}) {
    CAPTURE(key);
    const std::string scene = loose_scene("dt = 0.01\n" + std::string(key) + "\n");
    const std::string e = test::scene_error(scene);
    CHECK(e.find("give lubrication.dt or lubrication.dt_max (with ") != std::string::npos);
    CHECK(e.find(std::string(key).substr(0, std::string(key).find(' '))) != std::string::npos);
  }
  const std::string e = test::scene_error(loose_scene("dt = 1e-20\n"));
  CHECK(e.find("below 1e-12 of the loading's time") != std::string::npos);
  CHECK(test::simulation_from(loose_scene("dt = 2e-12\n"), 1) != nullptr);
}

TEST_CASE("paste: a pressure or viscosity whose time unit double precision cannot hold is refused at its key") {
  // A pressure of 1e-320 Pa gave an infinite time unit: the run failed on its first step, with
  // inf and nan in the stats, and the message blamed lubrication.dt_max.
  std::string thin = loose_scene("");
  thin.replace(thin.find("pressure = 1.0"), 14, "pressure = 1e-320");
  const std::string e1 = test::scene_error(thin);
  CHECK(e1.find("time unit (eta a^(3-d) / P) is inf s") != std::string::npos);
  CHECK(e1.rfind("bad.toml:9:", 0) == 0);
  const std::string e2 = test::scene_error(test::paste_disks({.viscosity = 1e-320}));
  CHECK(e2.find("time unit (eta a^(3-d) / P) is ") != std::string::npos);
  CHECK(e2.find("e-32") != std::string::npos);
  // A shear far faster than the viscous time (Vi = 1e10): the default smallest step is of the
  // shear's time, not above the first step.
  std::string fast = loose_scene("");
  fast.replace(fast.find("[contact]"), 9, "[shear]\nviscous_number = 1e10\n[contact]");
  CHECK_NOTHROW(test::model_from(fast));
}
