// The parallel reductions: a maximum keeps a NaN of any block, whichever block it is in and
// however many threads share the range.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

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
