// Rough bases made by a run: grains frozen between steps (Simulation::freeze, the shell's
// `freeze`), saved, and taken by another scene as a frozen group (grains[].frozen_from).
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdio>

#include "silt/io.hpp"
#include "silt/run_job.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// 300 frictional spheres poured on a wall in a periodic box.
const char* kPour = R"(
[scene]
dimension = 3
seed = 2
[domain]
lo = [0, 0, 0]
hi = [6, 6, 20]
periodic = [true, true, false]
[gravity]
magnitude = 9.81
[contact]
model = "hooke"
k_n = 2e5
gamma_n = 50
friction = 0.5
[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
[[grains]]
count = 300
radius_min = 0.4
radius_max = 0.5
placement = "random"
[run]
dt = 1e-4
)";

// A chute whose base is the poured grains below z = 2 of `file`.
std::string chute(const std::string& file, const std::string& extra = "") {
  return std::string(R"(
[scene]
dimension = 3
[domain]
lo = [0, 0, 0]
hi = [6, 6, 20]
periodic = [true, true, false]
[gravity]
magnitude = 9.81
angle = 25
[contact]
model = "hooke"
k_n = 2e5
gamma_n = 50
friction = 0.5
[[grains]]
frozen_from = ")") +
         file + R"("
region_hi = [6, 6, 2]
)" + extra +
         R"(
[[grains]]
count = 100
radius = 0.45
placement = "random"
region_lo = [0, 0, 4]
[run]
dt = 1e-4
)";
}

}  // namespace

TEST_CASE("freeze: grains below a height stop for good, and the system becomes another one") {
  auto sim = test::simulation_from(kPour, 2);
  for (int k = 0; k < 8000; ++k) REQUIRE(sim->step());
  const uint64_t system_before = sim->model().scene_hash;
  const int64_t n = sim->freeze(2, true, 2.0);
  CHECK(n > 30);
  CHECK(sim->model().n_frozen == n);
  CHECK(sim->model().scene_hash != system_before);  // a checkpoint now belongs to a new system
  const State frozen_at = sim->state();
  for (int k = 0; k < 500; ++k) REQUIRE(sim->step());
  const State& s = sim->state();
  int64_t still = 0;
  for (int64_t i = 0; i < s.n; ++i) {
    if (!s.particle_frozen[i]) continue;
    const int64_t j = index_of_ids(frozen_at)[s.particle_id[i]];
    bool same = true;
    for (int k = 0; k < 3; ++k) same = same && s.particle_x[3 * i + k] == frozen_at.particle_x[3 * j + k];
    still += same;
  }
  CHECK(still == n);
  // No pair of two frozen grains is listed.
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p)
      CHECK_FALSE((s.particle_frozen[i] && s.particle_frozen[s.pair_j[p]]));
  // Under a deforming box it is refused.
  auto sheared = test::simulation_from(test::frictional_gas(3, 0.5, 0.0, 0.0), 1);
  CHECK_THROWS_AS(sheared->freeze(2, true, 1.0), std::invalid_argument);
}

TEST_CASE(
    "freeze: a checkpoint saved after it restores in a new simulation of the scene, which freezes the grains too") {
  // The frozen flags were part of the system's identity: the scene's own simulation refused the
  // checkpoint ("the grains differ"), so a session's freeze could not be continued in another.
  const std::string file = "freeze_test_after.ckpt", before = "freeze_test_before.ckpt";
  auto sim = test::simulation_from(kPour, 1);
  for (int k = 0; k < 200; ++k) REQUIRE(sim->step());
  write_checkpoint(before, sim->model(), sim->state());
  const int64_t n = sim->freeze(2, true, 3.0);
  REQUIRE(n > 0);
  write_checkpoint(file, sim->model(), sim->state());
  for (int k = 0; k < 100; ++k) REQUIRE(sim->step());
  auto again = test::simulation_from(kPour, 1);
  CHECK_THROWS_WITH_AS(
      read_checkpoint(file, again->model()),
      doctest::Contains((std::to_string(n) + " of them are frozen in the checkpoint and free in the scene").c_str()),
      IoError);
  std::vector<uint8_t> frozen;
  State st = read_checkpoint(file, again->model(), nullptr, &frozen);
  CHECK(std::count(frozen.begin(), frozen.end(), 1) == n);
  CHECK(again->freeze_grains(frozen) == n);
  CHECK(again->model().scene_hash == sim->model().scene_hash);
  again->restore(std::move(st));
  for (int k = 0; k < 100; ++k) REQUIRE(again->step());
  CHECK(state_hash(again->state()) == state_hash(sim->state()));
  // The other way, grains frozen in the simulation and free in the checkpoint, is another system.
  CHECK_THROWS_WITH_AS(
      read_checkpoint(before, again->model(), nullptr, &frozen),
      doctest::Contains((std::to_string(n) + " frozen in the scene are free in the checkpoint").c_str()), IoError);
  std::remove(file.c_str());
  std::remove(before.c_str());
}

TEST_CASE("frozen_from: a checkpoint's grains in a region become a frozen group of another scene") {
  auto sim = test::simulation_from(kPour, 2);
  for (int k = 0; k < 8000; ++k) REQUIRE(sim->step());
  const std::string file = "freeze_test_pour.ckpt";
  write_checkpoint(file, sim->model(), sim->state());
  const State& s = sim->state();
  int64_t below = 0;
  for (int64_t i = 0; i < s.n; ++i) below += s.particle_x[3 * i + 2] <= 2.0;
  const Model m = test::model_from(chute(file));
  CHECK(m.n_frozen == below);
  CHECK(m.n_grains == below + 100);
  // In the order of the checkpoint's ids, at their positions, with their radii.
  const auto index = index_of_ids(s);
  int64_t q = 0;
  for (int64_t id = 0; id < s.n; ++id) {
    const int64_t i = index[id];
    if (s.particle_x[3 * i + 2] > 2.0) continue;
    CHECK(m.init.radius[q] == s.particle_r[i]);
    CHECK(m.init.x[3 * q + 2] == s.particle_x[3 * i + 2]);
    CHECK(m.init.frozen[q] == 1);
    ++q;
  }
  auto chute_sim = test::simulation_from(chute(file), 1);
  for (int k = 0; k < 300; ++k) REQUIRE(chute_sim->step());
  // The checkpoint is an input of the scene: a run's outputs never overwrite it.
  REQUIRE(chute_sim->model().checkpoints_read == std::vector<std::string>{file});
  for (const auto out : {&RunJobOptions::stats, &RunJobOptions::summary, &RunJobOptions::save}) {
    RunJobOptions o;
    o.*out = file;
    CHECK_THROWS_WITH_AS(RunJob(*chute_sim, o), doctest::Contains("is a checkpoint the scene reads (frozen_from)"),
                         IoError);
  }
  // What the group cannot be told.
  CHECK(test::scene_error(chute(file, "count = 10")).find("count does not apply") != std::string::npos);
  CHECK(test::scene_error(chute(file, "frozen = false")).find("are frozen") != std::string::npos);
  CHECK(test::scene_error(chute("no_such.ckpt")).find("no such file") != std::string::npos);
  std::remove(file.c_str());
}
