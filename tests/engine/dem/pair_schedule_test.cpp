// The pair schedule: blocks of one colour never write the same grain, every block is scheduled
// once, grains in cell order need only a few colours, and its graph makes the blocks that write
// a grain run in colour order whatever order the ready blocks are taken in, each grain's sums
// cleared first.
#include <doctest/doctest.h>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <random>
#include <set>

#include "dem/pair_schedule.hpp"
#include "dem/workspace.hpp"
#include "silt/scene.hpp"
#include "support/scenes.hpp"

using namespace silt;
using silt::dem::PairSchedule;

namespace {

constexpr int64_t B = PairSchedule::kBlock;

// The grain blocks that block b writes.
std::set<int32_t> written_by(int64_t n, const std::vector<int32_t>& start, const std::vector<int32_t>& pj, int32_t b) {
  std::set<int32_t> t;
  for (int64_t i = b * B; i < std::min(n, (b + 1) * B); ++i) {
    t.insert(static_cast<int32_t>(i / B));
    for (int32_t p = start[i]; p < start[i + 1]; ++p) t.insert(static_cast<int32_t>(pj[p] / B));
  }
  return t;
}

// Runs the schedule's graph serially, taking a random ready block each time, and checks that the
// writers of every grain block come in colour order, the first of them clearing it.
void check_graph(int64_t n, const std::vector<int32_t>& start, const std::vector<int32_t>& pj, const PairSchedule& s,
                 std::mt19937& rng) {
  const int64_t nb = static_cast<int64_t>(s.blocks.size());
  std::vector<std::vector<int32_t>> expected(nb), seen(nb);
  std::vector<int> cleared(nb, 0);
  for (int32_t b : s.blocks)
    for (int32_t t : written_by(n, start, pj, b)) expected[t].push_back(b);
  std::vector<int32_t> waiting = s.n_before, ready = s.roots;
  int64_t runs = 0;
  while (!ready.empty()) {
    const size_t k = std::uniform_int_distribution<size_t>(0, ready.size() - 1)(rng);
    const int32_t b = ready[k];
    ready.erase(ready.begin() + static_cast<std::ptrdiff_t>(k));
    ++runs;
    for (int32_t k2 = s.clears_start[b]; k2 < s.clears_start[b + 1]; ++k2) {
      const int32_t t = s.clears[k2];
      CHECK(seen[t].empty());
      ++cleared[t];
    }
    for (int32_t t : written_by(n, start, pj, b)) {
      CHECK(cleared[t] == 1);
      seen[t].push_back(b);
    }
    for (int32_t k2 = s.after_start[b]; k2 < s.after_start[b + 1]; ++k2)
      if (--waiting[s.after[k2]] == 0) ready.push_back(s.after[k2]);
  }
  CHECK(runs == nb);
  CHECK(seen == expected);
}

// Checks the schedule of a half list; returns its number of colours.
int check_schedule(int64_t n, const std::vector<int32_t>& start, const std::vector<int32_t>& pj) {
  const PairSchedule s = dem::build_pair_schedule(n, start, pj);
  const int64_t nb = (n + B - 1) / B;
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
  std::mt19937 rng(11);
  for (int order = 0; order < 3; ++order) check_graph(n, start, pj, s, rng);
  return s.colours();
}

}  // namespace

TEST_CASE("pair schedule: random partners, no two blocks of a colour write the same grain") {
  std::mt19937 rng(7);
  for (int64_t n : {int64_t{1}, B - 1, B, B + 1, 3 * B + 500}) {
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
  CHECK(static_cast<int64_t>(test::dem_workspace(sim).schedule.blocks.size()) ==
        (s.n + PairSchedule::kBlock - 1) / PairSchedule::kBlock);
}

// The chute after one step (its list in cell order) and the schedule of that list.
struct ChuteList {
  Simulation sim{compile(load_scene_file(test::scene_path("chute"))), 1};
  PairSchedule schedule;
  ChuteList() {
    sim.step();
    schedule = dem::build_pair_schedule(sim.state().n, sim.state().nbr_start, sim.state().pair_j);
  }
};

TEST_CASE("pair schedule: the parallel pass runs each block once, after the blocks before it") {
  ChuteList chute;
  const State& st = chute.sim.state();
  PairSchedule& s = chute.schedule;
  const int64_t nb = static_cast<int64_t>(s.blocks.size());
  REQUIRE(nb > 8);
  std::vector<std::vector<int32_t>> writers(nb);  // of each grain block, in colour order
  for (int32_t b : s.blocks)
    for (int32_t t : written_by(st.n, st.nbr_start, st.pair_j, b)) writers[t].push_back(b);
  // The threads' shares: even (none given), lopsided, one of them empty, and shares made for
  // another number of threads (which do not fit and fall back to even ones).
  std::vector<double> skew(nb, 1.0);
  skew[0] = 10.0 * static_cast<double>(nb);
  const std::vector<std::pair<int, Shares>> splits = {
      {4, Shares{}},
      {2, balanced_shares(skew.data(), nb, 2)},
      {3, balanced_shares(skew.data(), nb, 3)},
      {2, even_shares(nb, 3)},
      {4, even_shares(nb, 4)},
  };
  REQUIRE(splits[1].second.begin[1] == 1);                          // the first block alone is half the cost
  REQUIRE(splits[2].second.begin[0] == splits[2].second.begin[1]);  // an empty share
  for (const auto& split : splits) {
    const int threads = split.first;
    const Shares& shares = split.second;  // a named reference: lambdas may not capture a binding in C++20
    CAPTURE(threads);
    tbb::task_arena arena(threads);
    for (int pass = 0; pass < 20; ++pass) {
      std::atomic<int64_t> clock{0};
      std::vector<int64_t> begin(nb, -1), end(nb, -1);
      std::vector<int> runs(nb, 0);
      arena.execute([&] {
        dem::run_pair_schedule(s, shares, nullptr, [&](int32_t b) {
          begin[b] = clock++;
          ++runs[b];
          end[b] = clock++;
        });
      });
      CHECK(std::count(runs.begin(), runs.end(), 1) == nb);
      for (const std::vector<int32_t>& w : writers)
        for (size_t k = 1; k < w.size(); ++k) CHECK(end[w[k - 1]] < begin[w[k]]);
    }
  }
}

TEST_CASE("pair schedule: a pass with shares adds each block's time to their costs") {
  ChuteList chute;
  PairSchedule& s = chute.schedule;
  const int64_t nb = static_cast<int64_t>(s.blocks.size());
  std::vector<double> cost(nb, 0.0);
  const Shares shares = even_shares(nb, 2);
  tbb::task_arena(2).execute([&] {
    dem::run_pair_schedule(s, shares, cost.data(), [&](int32_t b) {
      const auto t0 = std::chrono::steady_clock::now();
      while (std::chrono::steady_clock::now() - t0 < std::chrono::microseconds(50 * (b % 2 + 1))) {
      }
    });
  });
  for (int64_t b = 0; b < nb; ++b) CHECK(cost[b] >= 50e-6 * static_cast<double>(b % 2 + 1));
  // Shares made for another number of threads measure nothing.
  std::fill(cost.begin(), cost.end(), 0.0);
  const Shares three = even_shares(nb, 3);
  tbb::task_arena(2).execute([&] { dem::run_pair_schedule(s, three, cost.data(), [](int32_t) {}); });
  CHECK(std::count(cost.begin(), cost.end(), 0.0) == nb);
}

TEST_CASE("pair schedule: more threads than blocks") {
  // oneTBB caps its workers at the machine's cores unless told otherwise.
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 4);
  const int64_t n = 2 * PairSchedule::kBlock + 5;  // three blocks
  std::vector<int32_t> start(n + 1, 0), pj;
  for (int64_t i = 0; i < n; ++i) {
    if (i + 7 < n) pj.push_back(static_cast<int32_t>(i + 7));
    start[i + 1] = static_cast<int32_t>(pj.size());
  }
  PairSchedule s = dem::build_pair_schedule(n, start, pj);
  for (int pass = 0; pass < 50; ++pass) {
    std::vector<std::atomic<int>> runs(3);
    tbb::task_arena(4).execute(
        [&] { dem::run_pair_schedule(s, Shares{}, nullptr, [&](int32_t b) { runs[b].fetch_add(1); }); });
    for (const auto& r : runs) CHECK(r.load() == 1);
  }
}

TEST_CASE("pair schedule: each share lists the blocks that conflict with another share's first") {
  ChuteList chute;
  PairSchedule& s = chute.schedule;
  const int64_t nb = static_cast<int64_t>(s.blocks.size());
  for (int owners : {2, 3}) {
    CAPTURE(owners);
    const Shares shares = even_shares(nb, owners);
    dem::split_by_owner(s, shares);
    // Blocks with an edge of the graph (a conflict) to another owner's block.
    std::vector<int> edge(nb, 0);
    for (int64_t b = 0; b < nb; ++b)
      for (int32_t k = s.after_start[b]; k < s.after_start[b + 1]; ++k)
        if (shares.owner_of(b) != shares.owner_of(s.after[k])) edge[b] = edge[s.after[k]] = 1;
    int with_edge = 0;
    for (int t = 0; t < owners; ++t) {
      std::vector<int32_t> own(s.own.begin() + s.own_start[t], s.own.begin() + s.own_start[t + 1]);
      std::vector<int32_t> expected;
      for (int64_t b = shares.begin[t]; b < shares.begin[t + 1]; ++b) expected.push_back(static_cast<int32_t>(b));
      std::vector<int32_t> sorted = own;
      std::sort(sorted.begin(), sorted.end());
      CHECK(sorted == expected);
      // Every block with such an edge before every block without.
      CHECK(std::is_sorted(own.begin(), own.end(), [&](int32_t a, int32_t b) { return edge[a] > edge[b]; }));
      for (int32_t b : own) with_edge += edge[b];
    }
    CHECK(with_edge >= 2 * (owners - 1));  // the test means something: each boundary has blocks on both sides
  }
}
