// The pair schedule: blocks of one colour never write the same grain, every block is scheduled
// once, and grains in cell order need only a few colours.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>

#include "dem/pair_schedule.hpp"
#include "silt/scene.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// Checks the schedule of a half list; returns its number of colours.
int check_schedule(int64_t n, const std::vector<int32_t>& start, const std::vector<int32_t>& pj) {
  const PairSchedule s = dem::build_pair_schedule(n, start, pj);
  const int64_t B = PairSchedule::kBlock, nb = (n + B - 1) / B;
  std::vector<int32_t> blocks = s.blocks;
  std::sort(blocks.begin(), blocks.end());
  std::vector<int32_t> all(nb);
  for (int64_t b = 0; b < nb; ++b) all[b] = static_cast<int32_t>(b);
  CHECK(blocks == all);
  for (int c = 0; c < s.colours(); ++c) {
    std::vector<int32_t> writer(n, -1);  // the block of this colour that writes each grain
    for (int32_t k = s.colour_start[c]; k < s.colour_start[c + 1]; ++k) {
      const int32_t b = s.blocks[k];
      auto claim = [&](int64_t g) {
        if (writer[g] != -1 && writer[g] != b)
          FAIL_CHECK("colour " << c << ": grain " << g << " written by blocks " << writer[g] << " and " << b);
        writer[g] = b;
      };
      for (int64_t i = b * B; i < std::min(n, (b + 1) * B); ++i) {
        claim(i);
        for (int32_t p = start[i]; p < start[i + 1]; ++p) claim(pj[p]);
      }
    }
  }
  return s.colours();
}

}  // namespace

TEST_CASE("pair schedule: random partners, no two blocks of a colour write the same grain") {
  std::mt19937 rng(7);
  for (int64_t n : {1, 255, 256, 257, 3000}) {
    std::vector<int32_t> start(n + 1, 0), pj;
    for (int64_t i = 0; i < n; ++i) {
      std::set<int32_t> row;
      for (int k = 0; k < 4 && i + 1 < n; ++k)
        row.insert(static_cast<int32_t>(std::uniform_int_distribution<int64_t>(i + 1, n - 1)(rng)));
      pj.insert(pj.end(), row.begin(), row.end());
      start[i + 1] = static_cast<int32_t>(pj.size());
    }
    CAPTURE(n);
    check_schedule(n, start, pj);
  }
}

TEST_CASE("pair schedule: the list of a real packing in cell order needs few colours") {
  Simulation sim(compile(load_scene_file(test::scene_path("chute"))), 1);
  sim.step();  // builds the list and sorts the grains by cell
  const State& s = sim.state();
  const int colours = check_schedule(s.n, s.nbr_start, s.pair_j);
  CHECK(colours <= 8);
  CHECK(static_cast<int64_t>(s.scratch.schedule.blocks.size()) == (s.n + PairSchedule::kBlock - 1) / PairSchedule::kBlock);
}
