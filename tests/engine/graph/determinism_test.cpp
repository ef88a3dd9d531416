// Results do not depend on the number of threads: bitwise equal states after N steps
// (Box2D's test_determinism, for the serial executor and the flow graph at 2 and 4 threads).
#include <doctest/doctest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <vector>

#include "support/scenes.hpp"

using namespace silt;

namespace {

// Each scene holds over twice PairSchedule::kBlock grains, so that the pair loop runs three blocks
// or more, and the blocks that write a common grain are ordered across threads.
// Frictional polydisperse spheres poured on a wall in a periodic box: pairs, walls, rebuilds.
const char* kPour3d = R"(
[scene]
dimension = 3
seed = 11
[domain]
lo = [0, 0, 0]
hi = [8, 8, 44]
periodic = [true, true, false]
[gravity]
magnitude = 9.81
angle = 10
[contact]
model = "spring_dashpot"
restitution = 0.6
contact_time = 2e-3
friction = 0.4
[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
[[grains]]
count = 2640
radius_min = 0.3
radius_max = 0.45
placement = "random"
velocity = "gaussian"
temperature = 0.01
[run]
dt_over_tc = 0.05
)";

// Frictional disks compressed by a stress-controlled box; more than 1,024 of them, since smaller
// systems always run on the serial executor.
const char* kPack2d = R"(
[scene]
dimension = 2
seed = 5
[domain]
lo = [0, 0]
hi = [74, 74]
periodic = [true, true]
[box]
pressure = 1.0
[contact]
model = "linear"
k_n = 1e4
damping = 0.5
friction = 0.3
[[grains]]
count = 2400
radius_min = 0.35
radius_max = 0.5
placement = "random"
[run]
dt_over_tc = 0.05
)";

// Frictional spheres sheared by Lees-Edwards conditions while L_y follows the pressure, more
// than 1,024 of them so that grains are renumbered at list builds.
const char* kShear3d = R"(
[scene]
dimension = 3
seed = 3
[domain]
lo = [0, 0, 0]
hi = [14.3, 14.3, 14.3]
periodic = [true, true, true]
[box]
pressure = 1.0
controlled = [false, true, false]
mass_factor = 0.01
[shear]
inertial_number = 0.3
[contact]
model = "linear"
k_n = 1e4
damping = 0.5
friction = 0.4
[[grains]]
count = 2420
radius_min = 0.35
radius_max = 0.5
placement = "random"
velocity = "gaussian"
temperature = 0.05
[run]
dt_over_tc = 0.05
)";

// Frictional spheres in a periodic box with no wall and no gravity: the pairs are the only force,
// and a step whose end nothing sees kicks and moves the grains inside its pair loop
// (dem::kick_and_next_drift).
const char* kGas3d = R"(
[scene]
dimension = 3
seed = 7
[domain]
lo = [0, 0, 0]
hi = [16, 16, 16]
periodic = [true, true, true]
[contact]
model = "spring_dashpot"
restitution = 0.7
contact_time = 2e-3
friction = 0.4
[[grains]]
count = 2800
radius_min = 0.35
radius_max = 0.5
placement = "random"
velocity = "gaussian"
temperature = 0.05
[run]
dt_over_tc = 0.05
)";

uint64_t hash_after(const char* scene, int threads, int steps) {
  auto sim = test::simulation_from(scene, threads);
  for (int k = 0; k < steps; ++k) REQUIRE(sim->step());
  return state_hash(sim->state());
}

}  // namespace

TEST_CASE("the state hash after N steps is the same for 1, 2 and 4 threads") {
  // oneTBB caps its workers at the machine's cores unless told otherwise: on a 2-core machine the
  // 3- and 4-thread arenas would run on 2 threads. Allow 4, so that they do run 3 and 4 ways.
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 4);
  const int steps = test::compared_steps(1500);
  for (const char* scene : {kPour3d, kPack2d, kShear3d}) {
    const uint64_t h1 = hash_after(scene, 1, steps);
    CHECK(hash_after(scene, 2, steps) == h1);
    CHECK(hash_after(scene, 4, steps) == h1);
    CHECK(hash_after(scene, 3, steps) == h1);
  }
}

TEST_CASE("a run whose steps are not all seen ends in the same state for 1, 2, 3 and 4 threads") {
  // run() sees every 100th step here: in the others the second half kick is left to the next step
  // (walls: dem::late_kick_drift) or made with the next drift inside the pair loop (no walls).
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 4);
  for (const char* scene : {kGas3d, kPour3d}) {
    const uint64_t h = hash_after(scene, 1, 600);
    for (int threads : {1, 2, 3, 4}) {
      CAPTURE(threads);
      auto sim = test::simulation_from(scene, threads);
      RunOptions opt;
      opt.steps = 600;
      std::vector<uint64_t> seen;
      opt.hooks.push_back({100, [&](const State& st) { seen.push_back(st.step); }});
      REQUIRE(sim->run(opt).end == RunEnd::kDone);
      CHECK(seen.size() == 7);
      CHECK(state_hash(sim->state()) == h);
    }
  }
}

TEST_CASE("the hash sees a change of one bit") {
  auto sim = test::simulation_from(kPack2d, 1);
  sim->prepare();
  const uint64_t h = state_hash(sim->state());
  sim->state().particle_v[7] = std::nextafter(sim->state().particle_v[7], 1.0);
  CHECK(state_hash(sim->state()) != h);
}

TEST_CASE("a measurement made between runs runs on the simulation's threads") {
  // (The shell's print sampled in the caller's arena: every core, whatever --threads said.)
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 4);
  for (int threads : {1, 3}) {
    auto sim = test::simulation_from(kPour3d, threads);
    int seen = 0;
    sim->within([&] { seen = tbb::this_task_arena::max_concurrency(); });
    CHECK(seen == threads);
  }
}
