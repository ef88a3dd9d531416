// The cyclic loadings of Peyneau (2009) ch. 5 on a small paste (box.cycle): at every step the
// stresses of the grains, contacts and lubrication together, are the imposed ones of the cycle
// at that time (the box rows of the solve), over a whole cycle, and the box deforms the way they
// push it.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "shear/cycle_origin.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// 60 disks at random in a periodic 9 x 9 box, P = 1, eta = 1 (the time unit eta / P = 1): one
// cycle of period 4 and amplitude 0.2, the step at most a fiftieth of it.
const char* kCyclicPaste = R"(
[scene]
dimension = 2
seed = 3
[domain]
lo = [0, 0]
hi = [9, 9]
periodic = [true, true]
[box]
pressure = 1.0
cycle = "{kind}"
cycle_period = 4.0
cycle_amplitude = 0.2
[contact]
model = "linear"
k_n = 1e4
friction = 0.3
kt_over_kn = 0.5
[lubrication]
viscosity = 1.0
h_min_over_a = 1e-2
tolerance = 1e-11
dt_max = 0.08
[[grains]]
count = 60
radius_min = 0.35
radius_max = 0.5
placement = "random"
)";

struct CycleRecord {
  double worst = 0;       // largest |sigma_aa - Sigma_aa(t)| / P over the steps
  double lowest = 1e300;  // smallest and largest Sigma_xx - Sigma_yy met, / P
  double highest = -1e300;
  double strain_half = 0;  // ln(L_x/L_x0) - ln(L_y/L_y0) at the first step past half a cycle
  double cycle_error = 0;  // largest |cycle - t / period|
  double shares = 0;       // largest |p_cont_ratio + p_lub_ratio - 1|
  int64_t steps = 0;
};

// One cycle of the given kind; `imposed(t, axis)` is the cycle's stress as the thesis writes it.
template <class Imposed>
CycleRecord run_cycle(const std::string& kind, Imposed imposed) {
  std::string scene = kCyclicPaste;
  scene.replace(scene.find("{kind}"), 6, kind);
  auto sim = test::simulation_from(scene, 1);
  const Model& m = sim->model();
  const double P = 1.0, period = 4.0;
  const double lx0 = sim->state().box.len[0], ly0 = sim->state().box.len[1];
  const Observer obs(m, {"stress.xx", "stress.yy", "cycle", "p_cont_ratio", "p_lub_ratio"});
  CycleRecord rec;
  bool half = false;
  RunOptions opt;
  opt.time = period;
  opt.hooks.push_back({1, [&](const State& s) {
                         const auto v = obs.sample(m, s);
                         const double sxx = imposed(s.t, 0), syy = imposed(s.t, 1);
                         rec.worst = std::max({rec.worst, std::abs(v[0] - sxx) / P, std::abs(v[1] - syy) / P});
                         rec.lowest = std::min(rec.lowest, (sxx - syy) / P);
                         rec.highest = std::max(rec.highest, (sxx - syy) / P);
                         rec.cycle_error = std::max(rec.cycle_error, std::abs(v[2] - s.t / period));
                         rec.shares = std::max(rec.shares, std::abs(v[3] + v[4] - 1));
                         if (!half && s.t >= period / 2) {
                           half = true;
                           rec.strain_half = std::log(s.box.len[0] / lx0) - std::log(s.box.len[1] / ly0);
                         }
                         ++rec.steps;
                       }});
  const RunReport r = sim->run(opt);
  if (r.end == RunEnd::kFailed) MESSAGE(sim->state().failure.message);
  CHECK(r.end == RunEnd::kDone);
  CHECK(sim->state().t >= period);
  return rec;
}

}  // namespace

TEST_CASE("paste: the alternating cycle imposes Sigma_xx = P (1 + d sin wt) and Sigma_yy = P (1 - d sin wt)") {
  const double d = 0.2, w = 2 * std::numbers::pi / 4.0;
  const CycleRecord r = run_cycle("alternating", [&](double t, int axis) {
    return axis == 0 ? 1.0 + d * std::sin(w * t) : 1.0 - d * std::sin(w * t);  // eq. 5.3-5.4
  });
  CAPTURE(r.steps);
  CHECK(r.steps >= 50);
  // The box rows of each solve hold the total stress at the imposed one; the solve's relative
  // residual is at most 1e-11 of a right-hand side of the order of P times the area (81).
  CHECK(r.worst < 1e-8);
  // The whole cycle was imposed: the deviator went to +-2 d P (sampled every step, at most a
  // fiftieth of the period apart: within 1 - cos(2 pi / 100) = 2e-3 of its extremes).
  CHECK(r.highest == doctest::Approx(2 * d).epsilon(3e-3));
  CHECK(r.lowest == doctest::Approx(-2 * d).epsilon(3e-3));
  CHECK(r.cycle_error < 1e-12);
  // The shares of the imposed stresses' mean at that time (biaxial cycles raise it above P).
  CHECK(r.shares < 1e-7);
  // The first half cycle presses harder along x: the box gets narrower along x than along y.
  CHECK(r.strain_half < 0);
}

TEST_CASE("paste: the biaxial cycle imposes Sigma_xx = P and Sigma_yy = P (1 + d (1 - cos wt))") {
  const double d = 0.2, w = 2 * std::numbers::pi / 4.0;
  const CycleRecord r = run_cycle("biaxial", [&](double t, int axis) {
    return axis == 0 ? 1.0 : 1.0 + d * (1 - std::cos(w * t));  // eq. 5.15-5.16
  });
  CAPTURE(r.steps);
  CHECK(r.steps >= 50);
  CHECK(r.worst < 1e-8);
  // The deviator Sigma_xx - Sigma_yy from 0 to -2 d P and back; never positive.
  CHECK(r.highest <= 1e-12);
  CHECK(r.lowest == doctest::Approx(-2 * d).epsilon(3e-3));
  CHECK(r.cycle_error < 1e-12);
  // The shares of the imposed stresses' mean at that time (biaxial cycles raise it above P).
  CHECK(r.shares < 1e-7);
  // y always pressed harder: the box gets narrower along y than along x.
  CHECK(r.strain_half > 0);
}

TEST_CASE("paste: a cycle period steered mid-run goes on from the phase reached, and replaces a viscous number") {
  // The phase was recomputed as w_new t: a period doubled at t = 1 (a quarter cycle) put the cycles
  // back to an eighth, a jump of the imposed stresses, and `cycle` ran backwards.
  std::string scene = kCyclicPaste;
  scene.replace(scene.find("{kind}"), 6, "alternating");
  auto sim = test::simulation_from(scene, 1);
  while (sim->state().t < 1.0) REQUIRE(sim->step());
  const double t1 = sim->state().t;
  const Observer obs(sim->model(), {"cycle"});
  const double before = obs.sample(sim->model(), sim->state())[0];
  auto imposed_xx = [&] {
    return sim->model().box_control.stress(0, shear::cycle_origin(sim->model(), sim->state()), t1);
  };
  const double sxx = imposed_xx();
  Model& m = sim->model_for_steering();
  REQUIRE(steer(m, parse_override("box.cycle_period=8.0")) == "");
  CHECK(obs.sample(sim->model(), sim->state())[0] == doctest::Approx(before).epsilon(1e-14));
  CHECK(imposed_xx() == doctest::Approx(sxx).epsilon(1e-14));
  for (int k = 0; k < 5; ++k) REQUIRE(sim->step());
  const double dt = sim->state().t - t1;
  CHECK(obs.sample(sim->model(), sim->state())[0] == doctest::Approx(before + dt / 8.0).epsilon(1e-12));
  // Given as a viscous number w eta / P instead: it replaces the period (both were refused).
  REQUIRE(steer(sim->model_for_steering(), parse_override("box.cycle_viscous_number=0.5")) == "");
  CHECK(sim->model().box_control.cycle_omega == doctest::Approx(0.5 / sim->model().a_max));  // Vi P / (eta a), 2D
  CHECK(sim->model().desc.has("box.cycle_period") == false);
}

TEST_CASE("paste: a checkpoint restored under another cycle period goes on from the phase it holds") {
  // The phase's origin was in the model: restored under a period of 8, the cycles started again
  // from w t, a jump of the imposed stresses from where the checkpoint's run had them.
  std::string scene = kCyclicPaste;
  scene.replace(scene.find("{kind}"), 6, "alternating");
  auto a = test::simulation_from(scene, 1);
  while (a->state().t < 1.0) REQUIRE(a->step());
  const std::string path = "cyclic_origin_test.ckpt";
  write_checkpoint(path, a->model(), a->state());
  const double t1 = a->state().t;
  const Observer obs(a->model(), {"cycle"});
  const double before = obs.sample(a->model(), a->state())[0];
  REQUIRE(steer(a->model_for_steering(), parse_override("box.cycle_period=8.0")) == "");
  for (int k = 0; k < 5; ++k) REQUIRE(a->step());

  std::string slower = scene;
  slower.replace(slower.find("cycle_period = 4.0"), 18, "cycle_period = 8.0");
  auto b = test::simulation_from(slower, 1);
  b->restore(read_checkpoint(path, b->model()));
  std::remove(path.c_str());
  CHECK(obs.sample(b->model(), b->state())[0] == doctest::Approx(before).epsilon(1e-14));
  for (int k = 0; k < 5; ++k) REQUIRE(b->step());
  const double dt = b->state().t - t1;
  CHECK(obs.sample(b->model(), b->state())[0] == doctest::Approx(before + dt / 8.0).epsilon(1e-12));
  // A checkpoint without an origin (of a scene without cycles, or older): w t, and a period steered
  // before its first step goes on from there (it went back to w_new t).
  auto d = test::simulation_from(scene, 1);
  State bare = a->state();
  bare.module_field(shear::cycle_origin_field()).clear();
  d->restore(bare);
  const double t2 = d->state().t, at_restore = obs.sample(d->model(), d->state())[0];
  CHECK(at_restore == doctest::Approx(t2 / 4.0).epsilon(1e-14));
  REQUIRE(steer(d->model_for_steering(), parse_override("box.cycle_period=8.0")) == "");
  CHECK(obs.sample(d->model(), d->state())[0] == doctest::Approx(at_restore).epsilon(1e-14));
  REQUIRE(d->step());
  CHECK(obs.sample(d->model(), d->state())[0] ==
        doctest::Approx(at_restore + (d->state().t - t2) / 8.0).epsilon(1e-12));
  // A new state starts the cycles at phase 0 again.
  auto c = test::simulation_from(slower, 1);
  REQUIRE(c->step());
  CHECK(obs.sample(c->model(), c->state())[0] == doctest::Approx(c->state().t / 8.0).epsilon(1e-14));
}

TEST_CASE("paste: the dry compression's model names the DEM's step in its failures") {
  // (a non-finite velocity in a paste's compression advised lowering lubrication.dt_max, which the
  // compression does not use)
  std::string scene = kCyclicPaste;
  scene.replace(scene.find("{kind}"), 6, "alternating");
  const Model m = test::model_from(scene);
  CHECK(m.dt_key == "lubrication.dt_max");
  const Model dry = compression_model(m);
  CHECK(dry.dt_key == "run.dt");
  CHECK_FALSE(dry.velocities_solved);
}
