// The owned loops (core/owned.hpp): every block once whatever the shares and the threads, each
// share run whole by one thread (its own when it comes), maxima that keep a NaN, shares balanced
// by cost and moved only when that pays.
#include <doctest/doctest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

#include "core/owned.hpp"

using namespace silt;

TEST_CASE("owned shares: even, balanced by cost, and the owner of each block") {
  const Shares even = even_shares(18, 2);
  CHECK(even.begin[0] == 0);
  CHECK(even.begin[1] == 9);
  CHECK(even.begin[2] == 18);
  CHECK(even.owner_of(8) == 0);
  CHECK(even.owner_of(9) == 1);
  CHECK(even.fits(18, 2));
  CHECK_FALSE(even.fits(18, 3));
  CHECK_FALSE(even.fits(17, 2));
  // The chute's pair loop: the first blocks (the dense bed) cost three times the last ones.
  std::vector<double> cost(18, 1.0);
  for (int b = 0; b < 9; ++b) cost[b] = 3.0;
  const Shares bal = balanced_shares(cost.data(), 18, 2);
  CHECK(bal.begin[1] == 6);  // 6 x 3 = 18 against 3 x 3 + 9 = 18
  CHECK(largest_share(bal, cost.data()) == 18.0);
  CHECK(largest_share(even, cost.data()) == 27.0);
  for (int64_t b = 0; b < 18; ++b) CHECK(bal.owner_of(b) == (b < 6 ? 0 : 1));
  // Nothing measured: even shares. One dear block: a share of its own; the empty shares hold none.
  std::vector<double> none(18, 0.0);
  CHECK(balanced_shares(none.data(), 18, 2).begin == even.begin);
  std::vector<double> one(18, 0.0);
  one[4] = 1.0;
  const Shares lone = balanced_shares(one.data(), 18, 3);
  CHECK(lone.begin[3] == 18);
  for (int t = 0; t < 3; ++t) CHECK(lone.begin[t] <= lone.begin[t + 1]);
  CHECK(largest_share(lone, one.data()) == 1.0);
}

TEST_CASE("owned loops: every block once, each share on one thread, on 1 to 4 threads") {
  const int64_t n = 9 * kOwnedBlock + 100;  // 10 blocks, the last short
  const int64_t nb = 10;
  std::vector<double> lopsided(nb, 1.0);
  lopsided[0] = 100.0;
  for (int threads : {1, 2, 3, 4}) {
    const std::vector<Shares> splits = {Shares{}, even_shares(nb, threads),
                                        balanced_shares(lopsided.data(), nb, threads), even_shares(nb, threads + 1)};
    for (const Shares& shares : splits)
      for (int pass = 0; pass < 20; ++pass) {
        CAPTURE(threads);
        std::vector<std::atomic<int>> hits(static_cast<size_t>(n));
        std::vector<int> slot(nb, -1);
        tbb::task_arena(threads).execute([&] {
          owned_for(n, shares, nullptr, [&](int64_t b, int64_t e) {
            CHECK(b % kOwnedBlock == 0);
            CHECK(e == std::min(n, b + kOwnedBlock));
            for (int64_t i = b; i < e; ++i) hits[i].fetch_add(1);
            slot[b / kOwnedBlock] = my_slot();
          });
        });
        int64_t once = 0;
        for (const auto& h : hits) once += h.load() == 1;
        CHECK(once == n);
        // A share runs on one thread: its blocks all carry the same slot.
        if (threads > 1 && shares.fits(nb, threads))
          for (int t = 0; t < threads; ++t)
            for (int64_t b = shares.begin[t]; b + 1 < shares.begin[t + 1]; ++b) CHECK(slot[b] == slot[b + 1]);
      }
  }
}

TEST_CASE("owned loops: more threads than blocks") {
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 4);
  const int64_t n = kOwnedBlock + 3;  // two blocks
  for (int pass = 0; pass < 50; ++pass) {
    std::vector<std::atomic<int>> runs(2);
    tbb::task_arena(4).execute(
        [&] { owned_for(n, Shares{}, nullptr, [&](int64_t b, int64_t) { runs[b / kOwnedBlock].fetch_add(1); }); });
    for (const auto& r : runs) CHECK(r.load() == 1);
  }
}

TEST_CASE("owned loops: costs are measured only with shares that fit") {
  const int64_t n = 6 * kOwnedBlock;
  std::vector<double> cost(6, 0.0);
  const Shares shares = even_shares(6, 2);
  auto spin = [](int64_t, int64_t) {
    volatile double x = 0;
    for (int k = 0; k < 20000; ++k) x = x + 1.0;
  };
  tbb::task_arena(2).execute([&] { owned_for(n, shares, cost.data(), spin); });
  for (double c : cost) CHECK(c > 0.0);
  std::fill(cost.begin(), cost.end(), 0.0);
  tbb::task_arena(3).execute([&] { owned_for(n, shares, cost.data(), spin); });  // made for 2 threads
  for (double c : cost) CHECK(c == 0.0);
}

TEST_CASE("owned maxima keep a NaN and equal the serial maximum on 1 to 4 threads") {
  const int64_t n = 5 * kOwnedBlock + 7;
  std::vector<double> v(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) v[i] = std::sin(0.37 * static_cast<double>(i));
  v[3 * kOwnedBlock + 5] = 1.5;
  auto block_max = [&](int64_t b, int64_t e) {
    std::array<double, 2> r{0, 0};
    for (int64_t i = b; i < e; ++i) {
      r[0] = (v[i] > r[0] || std::isnan(v[i])) ? v[i] : r[0];
      r[1] = std::max(r[1], -v[i]);
    }
    return r;
  };
  for (int threads : {1, 2, 3, 4}) {
    CAPTURE(threads);
    std::array<double, 2> m{};
    tbb::task_arena(threads).execute([&] { m = owned_max<2>(n, even_shares(6, threads), nullptr, block_max); });
    CHECK(m[0] == 1.5);
    CHECK(m[1] == doctest::Approx(1.0).epsilon(1e-3));
    v[n - 1] = std::numeric_limits<double>::quiet_NaN();
    tbb::task_arena(threads).execute([&] { m = owned_max<2>(n, Shares{}, nullptr, block_max); });
    CHECK(std::isnan(m[0]));
    v[n - 1] = 0.0;
  }
}

TEST_CASE("owned shares fitted to loops that join one after the other") {
  // A pair loop whose first half of blocks costs three times the second, and a grain pass whose
  // blocks all cost the same: the best boundary balances the dearer loop more.
  LoopCosts cost(2, std::vector<double>(18, 0.0));
  for (int64_t b = 0; b < 18; ++b) {
    cost[0][b] = b < 9 ? 3.0 : 1.0;
    cost[1][b] = 2.0;
  }
  const Shares fit = fitted_shares(cost, 18, 2);
  // Every boundary tried by hand: the least joined time.
  double least = 1e300;
  int64_t at = -1;
  for (int64_t k = 0; k <= 18; ++k) {
    Shares s = even_shares(18, 2);
    s.begin[1] = k;
    if (joined_time(s, cost) < least) {
      least = joined_time(s, cost);
      at = k;
    }
  }
  CHECK(fit.begin[1] == at);
  CHECK(joined_time(fit, cost) == least);
  CHECK(at == 6);  // max(18, 18) + max(12, 24) = 42; at 7: max(21, 15) + max(14, 22) = 43
  // Balanced by the summed cost instead (5 against 3 a block): the boundary at 7, dearer.
  std::vector<double> sum(18);
  for (int64_t b = 0; b < 18; ++b) sum[b] = cost[0][b] + cost[1][b];
  CHECK(balanced_shares(sum.data(), 18, 2).begin[1] == 7);
  CHECK(joined_time(balanced_shares(sum.data(), 18, 2), cost) > least);
  // Three owners: balanced by the summed cost.
  CHECK(fitted_shares(cost, 18, 3).begin == balanced_shares(sum.data(), 18, 3).begin);
}

TEST_CASE("owned shares: rebalanced when that shortens the joined time by more than a twentieth") {
  const int64_t n = 18 * kOwnedBlock;
  tbb::task_arena(2).execute([&] {
    Shares shares;
    LoopCosts cost(2);
    rebalance(shares, cost, n);  // the first: even, nothing measured yet
    REQUIRE(shares.fits(18, 2));
    CHECK(shares.begin[1] == 9);
    CHECK(cost[0].size() == 18);
    CHECK(cost[1].size() == 18);
    // Costs within a few per cent of even: the shares stay, and the costs halve.
    for (int64_t b = 0; b < 18; ++b) cost[0][b] = b < 9 ? 1.04 : 1.0;
    rebalance(shares, cost, n);
    CHECK(shares.begin[1] == 9);
    CHECK(cost[0][0] == doctest::Approx(0.52));
    // The first half three times as dear: they move.
    for (int64_t b = 0; b < 18; ++b) cost[0][b] = b < 9 ? 3.0 : 1.0;
    rebalance(shares, cost, n);
    CHECK(shares.begin[1] == 6);
    // Another number of grains: even again, the costs restarted.
    rebalance(shares, cost, 20 * kOwnedBlock);
    CHECK(shares.begin[1] == 10);
    CHECK(cost[0].size() == 20);
    CHECK(cost[1].size() == 20);
  });
  Shares one;
  LoopCosts cost(2);
  tbb::task_arena(1).execute([&] { rebalance(one, cost, n); });
  CHECK(one.owners == 0);  // one thread: no shares
}
