// The parallel reductions: a maximum keeps a NaN of any block, whichever block it is in and
// however many threads share the range. And the pinned loop covers its range once.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <cmath>
#include <vector>

#include "core/parallel.hpp"

using namespace silt;

TEST_CASE("parallel_max keeps a NaN whichever block holds it, on 1 and 2 threads") {
  const int64_t n = 4096, grain = 16;
  for (int threads : {1, 2})
    for (int64_t at : {int64_t{0}, int64_t{7}, n / 2, n - 1}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      std::vector<double> v(static_cast<size_t>(n), 1.0);
      v[at] = std::nan("");
      v[n / 3] = 5.0;
      const auto m = parallel_max<2>(n, grain, [&](int64_t b, int64_t e) {
        std::array<double, 2> r{0, 0};
        for (int64_t i = b; i < e; ++i) {
          r[0] = (v[i] > r[0] || v[i] != v[i]) ? v[i] : r[0];
          r[1] = std::max(r[1], i == at ? 0.0 : v[i]);  // no NaN: the plain maximum
        }
        return r;
      });
      CAPTURE(threads);
      CAPTURE(at);
      CHECK(std::isnan(m[0]));
      CHECK(m[1] == 5.0);
    }
}

TEST_CASE("parallel_for_pinned visits every index once, in blocks of at least the grain, on 1 to 4 threads") {
  for (int threads : {1, 2, 4})
    for (int64_t n : {int64_t{0}, int64_t{1}, int64_t{7}, int64_t{64}, int64_t{1000}}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      const int64_t grain = 8;
      std::vector<int> seen(static_cast<size_t>(n), 0);
      std::atomic<int> short_blocks{0};
      parallel_for_pinned(n, grain, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) ++seen[static_cast<size_t>(i)];
        // A block shorter than the grain only when the whole range is.
        if (e - b < grain && n >= grain) ++short_blocks;
      });
      CAPTURE(threads);
      CAPTURE(n);
      for (int64_t i = 0; i < n; ++i) CHECK(seen[static_cast<size_t>(i)] == 1);
      CHECK(short_blocks.load() == 0);
    }
}
