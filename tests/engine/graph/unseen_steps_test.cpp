// Simulation::run stores the pair forces (pair_f) only in the steps whose end something sees
// (State::boundary_seen), and a DEM step whose end nothing sees leaves its second half kick to the
// next step (dem::late_kick_drift). The dynamics do not change (same bits); in between, the stored
// forces are stale and the velocities half kicked; every boundary that a hook, a request, an interrupt or the end of
// the run sees is the same, bit for bit, as with the forces stored in every step; and so is a failure.
#include <doctest/doctest.h>

#include <atomic>
#include <limits>
#include <string>
#include <vector>

#include "support/scenes.hpp"

using namespace silt;

namespace {

// A frictional gas in a periodic box (its neighbour list in the default contact skin).
const std::string kBed = test::frictional_gas(3, 0.0, 0.0, 0.06);

constexpr int64_t kSteps = 90;

// State hashes (pair forces included) after each step, forces stored in every step; [0] is
// the prepared state (forces of t = 0), as run() shows it.
std::vector<uint64_t> reference_hashes() {
  auto sim = test::simulation_from(kBed);
  sim->prepare();
  std::vector<uint64_t> h{state_hash(sim->state())};
  for (int64_t k = 0; k < kSteps; ++k) {
    INFO(sim->state().failure.message);
    REQUIRE(sim->step());
    h.push_back(state_hash(sim->state()));
  }
  return h;
}

// Whether the stored pair force of some touching pair differs from the one of the reference
// simulation at the same step.
bool stale_forces(const State& s, const State& ref) {
  for (int64_t p = 0; p < s.n_pairs(); ++p)
    for (int k = 0; k < 3; ++k)
      if (s.pair_f[3 * p + k] != ref.pair_f[3 * p + k]) return true;
  return false;
}

}  // namespace

TEST_CASE("run() stores pair forces only for the boundaries it shows") {
  const std::vector<uint64_t> ref = reference_hashes();
  auto exact = test::simulation_from(kBed);  // kept in step with the run, forces in every step
  exact->prepare();
  auto sim = test::simulation_from(kBed);
  std::vector<int64_t> seen;
  bool stale_between = false, kick_left = false;
  RunOptions opt;
  opt.steps = kSteps;
  opt.hooks.push_back({30, [&](const State& s) {
                         seen.push_back(s.step);
                         CHECK(state_hash(s) == ref[s.step]);
                       }});
  // Asked before each step that nothing else observes: look at the state left by the last one.
  opt.boundary_wanted = [&] {
    const State& s = sim->state();
    while (exact->state().step < s.step) REQUIRE(exact->step());
    // On one thread the kick is left to the next step, the positions are the reference's (with
    // two, the pair loop would already have moved them: determinism_test).
    CHECK(s.particle_x == exact->state().particle_x);
    CHECK(s.pair_hist == exact->state().pair_hist);
    if (s.step % 30 != 0 && stale_forces(s, exact->state())) stale_between = true;
    if (s.step % 30 != 0 && s.particle_v != exact->state().particle_v) kick_left = true;
    return false;
  };
  const RunReport r = sim->run(opt);
  CHECK(r.end == RunEnd::kDone);
  CHECK(seen == std::vector<int64_t>{0, 30, 60, 90});
  CHECK(stale_between);  // the forces were not stored in between
  CHECK(kick_left);      // nor the second half kicks made
  CHECK(state_hash(sim->state()) == ref[kSteps]);
}

TEST_CASE("an interrupt or a request at an unseen boundary is served at the next complete one") {
  const std::vector<uint64_t> ref = reference_hashes();
  SUBCASE("interrupt: one more step, then stop") {
    auto sim = test::simulation_from(kBed);
    std::atomic<bool> stop{false};
    RunOptions opt;
    opt.steps = kSteps;
    opt.interrupt = &stop;
    opt.boundary_wanted = [&] {
      if (sim->state().step == 44) stop = true;  // arrives while step 45 runs without forces
      return false;
    };
    const RunReport r = sim->run(opt);
    CHECK(r.end == RunEnd::kInterrupted);
    CHECK(r.steps_done == 46);
    CHECK(state_hash(sim->state()) == ref[46]);
  }
  SUBCASE("request: served after a step that stores the forces") {
    auto sim = test::simulation_from(kBed);
    std::vector<int64_t> served;
    bool pending = false;
    RunOptions opt;
    opt.steps = kSteps;
    opt.boundary_wanted = [&] {
      if (sim->state().step == 50) pending = true;
      return pending;
    };
    opt.between_steps = [&] {
      if (!pending) return;
      pending = false;
      served.push_back(sim->state().step);
      CHECK(state_hash(sim->state()) == ref[sim->state().step]);
    };
    const RunReport r = sim->run(opt);
    CHECK(r.end == RunEnd::kDone);
    CHECK(served == std::vector<int64_t>{51});
    CHECK(state_hash(sim->state()) == ref[kSteps]);
  }
}

TEST_CASE("a failure in an unseen step is the same, and the last good state is exact") {
  // One grain's velocity is not finite: the first step's drift finds it. Or its spin: the drift
  // moves it all the same, and the first step's second half kick finds it; run() leaves that
  // kick to the second step (dem::late_kick_drift), which must still name the first.
  for (const int component : {1, -1}) {  // a velocity component, or the spin's (-1)
    CAPTURE(component);
    auto failing = [&] {
      auto sim = test::simulation_from(kBed);
      State& s = sim->state();
      for (int64_t i = 0; i < s.n; ++i)
        if (s.particle_id[i] == 17) {
          double& x = component >= 0 ? s.particle_v[3 * i + component] : s.particle_w[3 * i];
          x = std::numeric_limits<double>::quiet_NaN();
        }
      return sim;
    };
    auto by_steps = failing();
    bool ok = true;
    for (int k = 0; k < 100000 && ok; ++k) ok = by_steps->step();
    REQUIRE_FALSE(ok);
    auto by_run = failing();
    RunOptions opt;
    opt.steps = 100000;
    REQUIRE(by_run->run(opt).end == RunEnd::kFailed);
    const StepFailure& want = by_steps->state().failure;
    const StepFailure& got = by_run->state().failure;
    CHECK(want.step == 1);
    CHECK(want.particle == 17);
    CHECK(got.step == want.step);
    CHECK(got.stage == want.stage);
    CHECK(got.particle == want.particle);
    CHECK(got.message == want.message);
    CHECK(state_hash(by_run->last_good_state()) == state_hash(by_steps->last_good_state()));
    // The spin's failure is found one step later in the run (the kick left to the next step).
    CHECK(by_run->state().step == want.step + (component < 0 ? 1 : 0));
  }
}
