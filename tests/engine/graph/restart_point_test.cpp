// The restart point of the last-good-state replay gives back the State taken, bit for bit
// (hash), from a flowing frictional bed where most listed pairs do not touch, including the sign
// of a zero spring; taking it leaves the State unchanged; and it is smaller than a full copy.
#include <doctest/doctest.h>

#include <cmath>

#include "graph/restart_point.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"
#include "support/scenes.hpp"

using namespace silt;

TEST_CASE("a restart point gives back the State taken, bit for bit") {
  Simulation sim(compile(load_scene_file(test::scene_path("chute"))), 2);
  for (int step = 0; step < 150; ++step) REQUIRE(sim.step());
  State& s = sim.state();
  // A pair apart with a -0 spring (a zero that a comparison with 0 would not see).
  int64_t apart = -1;
  for (int64_t p = 0; p < s.n_pairs() && apart < 0; ++p)
    if (!s.pair_touch[p]) apart = p;
  REQUIRE(apart >= 0);
  s.pair_hist[3 * apart + 1] = -0.0;
  const uint64_t before = state_hash(s);
  graph::RestartPoint rp;
  rp.take(s);
  CHECK(state_hash(s) == before);
  const State back = rp.give();
  CHECK(state_hash(back) == before);
  CHECK(std::signbit(back.pair_hist[3 * apart + 1]));
  int64_t touching = 0;
  for (uint8_t t : s.pair_touch) touching += t;
  CHECK(touching < s.n_pairs() / 2);  // the case the restart point is made for
}
