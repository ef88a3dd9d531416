// Block averaging on synthetic correlated series with a known error of the mean.
#include <doctest/doctest.h>

#include <cmath>

#include "core/rng.hpp"
#include "silt/io.hpp"

using namespace silt;

TEST_CASE("block averaging recovers the error of the mean of an AR(1) series") {
  // x_t = rho x_{t-1} + e_t with unit Gaussian e_t: variance 1/(1-rho^2), and for n >> tau the
  // variance of the mean is var (1+rho)/(1-rho) / n.
  const int64_t n = 1 << 17;
  for (double rho : {0.0, 0.5, 0.9, 0.98}) {
    CAPTURE(rho);
    double sum_ratio = 0;
    const int reps = 8;
    for (int rep = 0; rep < reps; ++rep) {
      Rng rng(42, rep);
      std::vector<double> x(n);
      double prev = rng.normal() / std::sqrt(1 - rho * rho);
      for (int64_t t = 0; t < n; ++t) x[t] = prev = rho * prev + rng.normal();
      const BlockAverage b = block_average(x);
      const double exact = std::sqrt((1.0 / (1 - rho * rho)) * (1 + rho) / (1 - rho) / n);
      CHECK(b.converged);
      sum_ratio += b.err / exact;
      CHECK(std::abs(b.mean) < 5 * exact);
    }
    // The estimate has a relative spread of roughly sqrt(2 / n_blocks); averaged over 8 series
    // it must be within 10 % of the exact error.
    CHECK(sum_ratio / reps == doctest::Approx(1.0).epsilon(0.1));
  }
}

TEST_CASE("block averaging of short and constant series") {
  CHECK(block_average({}).n == 0);
  const BlockAverage one = block_average({3.0});
  CHECK(one.mean == 3.0);
  CHECK(one.err == 0.0);
  const BlockAverage flat = block_average(std::vector<double>(100, 2.5));
  CHECK(flat.mean == 2.5);
  CHECK(flat.err == 0.0);
  // A short strongly correlated series cannot give a converged error.
  std::vector<double> ramp(32);
  for (int i = 0; i < 32; ++i) ramp[i] = i;
  CHECK_FALSE(block_average(ramp).converged);
}
