// The grains' stress solved to lubrication.stress_tolerance: at small h_min the lubrication
// multiplies the velocities' error by up to a / h_min, and a solve to the residual's tolerance
// alone gives stresses of any sign. Against a solve taken as far as round-off lets it.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "paste/solve.hpp"
#include "silt/io.hpp"
#include "silt/model.hpp"
#include "silt/observables.hpp"
#include "silt/simulation.hpp"
#include "support/files.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// paste_3d_shear's spheres, 512 of them in a box of half the side (the same Phi, 0.45), at
// h_min/a = 1e-12, with `extra` appended to [lubrication].
std::string spheres(const std::string& extra) {
  std::string s = test::read_file(test::scene_path("paste_3d_shear"));
  for (auto [from, to] : {std::pair<std::string, std::string>{"count = 4096", "count = 512"},
                          {"hi = [38.0, 38.0, 38.0]", "hi = [19.0, 19.0, 19.0]"},
                          {"h_min_over_a = 1e-3", "h_min_over_a = 1e-12\n" + extra}}) {
    REQUIRE(s.find(from) != std::string::npos);
    s.replace(s.find(from), from.size(), to);
  }
  return s;
}

using Stress = std::array<std::array<double, 3>, 3>;

double distance(const Stress& a, const Stress& b) {
  double sum = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) sum += (a[i][j] - b[i][j]) * (a[i][j] - b[i][j]);
  return std::sqrt(sum);
}

double norm(const Stress& a) { return distance(a, Stress{}); }

// The stress after each of `steps` steps, and the solver's estimate of its error.
struct Run {
  std::vector<Stress> stress;
  std::vector<double> estimate;
  std::vector<std::string> notices;
  uint64_t hash = 0;    // of the whole state
  uint64_t motion = 0;  // of the positions, velocities and lubrication forces alone
};

// The packing the scene's grains make compressed dry to Phi = 0.45 (prepare.phi), the same for
// every solver's setting.
const State& packing() {
  static const State p = prepare_packing(test::model_from(spheres("")), 1);
  return p;
}

Run run(const std::string& scene, int steps, int threads = 1) {
  auto sim = std::make_unique<Simulation>(test::model_from(scene), threads);
  sim->restore(packing());
  Run r;
  for (int k = 0; k < steps; ++k) {
    REQUIRE(sim->step());
    r.stress.push_back(measure(sim->model(), sim->state(), measure_part::kStress).stress);
    r.estimate.push_back(
        paste::stress_error_of(sim->state().module_field(paste::paste_fields().solver)[paste::kStressError]));
    for (std::string& n : sim->take_notices()) r.notices.push_back(std::move(n));
  }
  r.hash = state_hash(sim->state());
  for (const char* f : {"particle_x", "particle_v", "particle_w", "pair_f_lub"})
    r.motion = r.motion * 31 + field_hash(sim->state(), find_field(f)->id);
  return r;
}

}  // namespace

TEST_CASE("paste: the stress is solved to its own tolerance at h_min/a = 1e-12, where the residual's leaves it wrong") {
  constexpr int kSteps = 3;
  const Run reference = run(spheres("tolerance = 1e-14\nstress_tolerance = 1e-9"), kSteps);
  const Run checked = run(spheres(""), kSteps);  // stress_tolerance 1e-4, the default
  const Run unchecked = run(spheres("stress_tolerance = 0"), kSteps);
  double worst_checked = 0, worst_unchecked = 0;
  for (int k = 0; k < kSteps; ++k) {
    CAPTURE(k);
    const double scale = norm(reference.stress[k]);
    REQUIRE(scale > 0);
    worst_checked = std::max(worst_checked, distance(checked.stress[k], reference.stress[k]) / scale);
    worst_unchecked = std::max(worst_unchecked, distance(unchecked.stress[k], reference.stress[k]) / scale);
    // The estimate of the checked run is within its tolerance, and none where nothing is checked.
    CHECK(checked.estimate[k] > 0);
    CHECK(checked.estimate[k] <= 1e-4);
    CHECK(std::isnan(unchecked.estimate[k]));
  }
  // Measured: 6e-5 of the norm at worst with the check (its estimate is of the error's size, not
  // a bound: 10 times the tolerance allowed), 30 times the norm without it.
  CHECK(worst_checked < 1e-3);
  CHECK(worst_unchecked > 0.1);
  // Nothing said where the tolerance is met; the reference's 1e-9 is below round-off, said once.
  CHECK(checked.notices.empty());
  REQUIRE(reference.notices.size() == 1);
  CHECK(reference.notices[0].find("stress is accurate to about") != std::string::npos);
  CHECK(reference.notices[0].find("lubrication.stress_tolerance = 1e-09") != std::string::npos);
}

TEST_CASE("paste: the stress's further solves give the same bits on 1 and 2 threads") {
  const std::string scene = spheres("");
  CHECK(run(scene, 2, 1).hash == run(scene, 2, 2).hash);
}

TEST_CASE("paste: the stress's check takes no further solve at h_min/a = 1e-3: the same motion as without it") {
  std::string scene = spheres("");
  scene.replace(scene.find("h_min_over_a = 1e-12"), 20, "h_min_over_a = 1e-3");
  const Run checked = run(scene, 3);
  for (double e : checked.estimate) CHECK(e < 1e-6);
  std::string off = spheres("stress_tolerance = 0");
  off.replace(off.find("h_min_over_a = 1e-12"), 20, "h_min_over_a = 1e-3");
  CHECK(run(off, 3).motion == checked.motion);
}

TEST_CASE("paste: a stress left short is said once, and once when a steered tolerance is met again") {
  auto sim = std::make_unique<Simulation>(test::model_from(spheres("stress_tolerance = 1e-9")), 1);
  sim->restore(packing());
  REQUIRE(sim->step());
  std::vector<std::string> notes = sim->take_notices();
  REQUIRE(notes.size() == 1);  // (the first state's solve: round-off leaves 1e-7 or so)
  CHECK(notes[0].find("accurate to about") != std::string::npos);
  REQUIRE(sim->step());
  CHECK(sim->take_notices().empty());
  REQUIRE(steer(sim->model_for_steering(), parse_override("lubrication.stress_tolerance=1e-4")) == "");
  REQUIRE(sim->step());
  notes = sim->take_notices();
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].find("within lubrication.stress_tolerance = 0.0001 again") != std::string::npos);
  // Turned off, the check says nothing, and there is no estimate.
  REQUIRE(steer(sim->model_for_steering(), parse_override("lubrication.stress_tolerance=0")) == "");
  REQUIRE(sim->step());
  CHECK(sim->take_notices().empty());
  CHECK(
      std::isnan(paste::stress_error_of(sim->state().module_field(paste::paste_fields().solver)[paste::kStressError])));
}

TEST_CASE("paste: a stress left short by a steered h_min is said at the solve its change makes") {
  // The velocities are solved again when h_min changes (lubrication_resolve), before the next
  // step: that solve's note was lost, and the step's found nothing new to say.
  std::string scene = spheres("");
  scene.replace(scene.find("h_min_over_a = 1e-12"), 20, "h_min_over_a = 1e-3");
  auto sim = std::make_unique<Simulation>(test::model_from(scene), 1);
  sim->restore(packing());
  REQUIRE(sim->step());
  CHECK(sim->take_notices().empty());
  REQUIRE(steer(sim->model_for_steering(), parse_override("lubrication.h_min_over_a=1e-12")) == "");
  REQUIRE(steer(sim->model_for_steering(), parse_override("lubrication.stress_tolerance=1e-9")) == "");
  REQUIRE(sim->step());
  const std::vector<std::string> notes = sim->take_notices();
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].rfind("step 2: ", 0) == 0);  // (the solve again, the step's first stage)
  CHECK(notes[0].find("accurate to about") != std::string::npos);
}

TEST_CASE("paste: a state with no estimate of the stress's error (a direct solve, the check off) restores") {
  // Its estimate was kept as nan: the checkpoint was written, and refused as corrupt when read.
  for (const char* extra : {"solver = \"direct\"", "stress_tolerance = 0"}) {
    CAPTURE(extra);
    std::string scene = spheres(extra);
    scene.replace(scene.find("h_min_over_a = 1e-12"), 20, "h_min_over_a = 1e-3");
    auto a = std::make_unique<Simulation>(test::model_from(scene), 1);
    a->restore(packing());
    REQUIRE(a->step());
    const Observer obs(a->model(), {"solver.stress_error"});
    CHECK(std::isnan(obs.sample(a->model(), a->state())[0]));
    const std::string path = "stress_none_test.ckpt";
    write_checkpoint(path, a->model(), a->state());
    auto b = std::make_unique<Simulation>(test::model_from(scene), 1);
    b->restore(read_checkpoint(path, b->model()));
    std::remove(path.c_str());
    CHECK(state_hash(b->state()) == state_hash(a->state()));
    CHECK(std::isnan(obs.sample(b->model(), b->state())[0]));
  }
}
