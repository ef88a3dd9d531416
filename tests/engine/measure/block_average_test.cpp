// Block averaging on synthetic correlated series with a known error of the mean.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <vector>

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

namespace {

// The naive standard error of the mean at every blocking level, in two passes over the series
// kept in memory (level k: means of pairs of level k - 1, an odd last one left out).
std::vector<double> level_errors(std::vector<double> data, double& mean) {
  mean = 0;
  for (double v : data) mean += v;
  mean /= static_cast<double>(data.size());
  std::vector<double> err;
  while (data.size() >= 2) {
    const double m = static_cast<double>(data.size());
    double c0 = 0;
    for (double v : data) c0 += (v - mean) * (v - mean);
    err.push_back(std::sqrt(c0 / m / (m - 1)));
    std::vector<double> next(data.size() / 2);
    for (size_t i = 0; i < next.size(); ++i) next[i] = 0.5 * (data[2 * i] + data[2 * i + 1]);
    data.swap(next);
  }
  return err;
}

}  // namespace

TEST_CASE("block averaging one sample at a time: the levels' errors of a two-pass sum, Wolff's block") {
  // The streamed form keeps the sums of each level instead of the series; its errors are the
  // two-pass ones to rounding, also for a series far from zero whose fluctuations are 1e-9 of its
  // value (sums relative to the first sample), and the block it reports is the first level that
  // meets B^3 > 2 n (s_B / s_1)^4.
  // (no structured bindings: clang's CAPTURE cannot take one)
  for (const auto& series :
       {std::tuple{2, 0.0, 0.0, 1.0}, std::tuple{3, 0.5, 0.0, 1.0}, std::tuple{1000, 0.9, 0.0, 1.0},
        std::tuple{4097, 0.98, 0.0, 1.0}, std::tuple{1 << 16, 0.9, 0.8, 1e-9}, std::tuple{777, 0.0, 5.0, 0.0},
        std::tuple{1000, 0.0, 0.1, 0.0}}) {
    const int n = std::get<0>(series);
    const double rho = std::get<1>(series), offset = std::get<2>(series), scale = std::get<3>(series);
    CAPTURE(n);
    CAPTURE(rho);
    CAPTURE(offset);
    Rng rng(7, static_cast<uint64_t>(n));
    std::vector<double> x(static_cast<size_t>(n));
    double prev = 0;
    BlockAccumulator acc;
    for (int64_t t = 0; t < n; ++t) {
      prev = rho * prev + rng.normal();
      x[t] = offset + scale * prev;
      acc.add(x[t]);
    }
    double mean = 0;
    const std::vector<double> err = level_errors(x, mean);
    const BlockAverage b = acc.result();
    CHECK(b.n == n);
    CHECK(acc.count() == n);
    CHECK(b.mean == doctest::Approx(mean).epsilon(1e-14));
    if (scale == 0) {  // a constant series, also one not exact in binary (0.1): no error at all
      CHECK(b.err == 0);
      CHECK(b.converged);
      continue;
    }
    int level = 0;
    while ((int64_t{1} << level) < b.block) ++level;
    REQUIRE(level < static_cast<int>(err.size()));
    CHECK(std::abs(b.err - err[level]) <= 1e-9 * err[level]);
    auto meets = [&](int k) {
      const double bk = std::ldexp(1.0, k);
      return bk * bk * bk > 2.0 * n * std::pow(err[k] / err[0], 4);
    };
    CHECK(b.converged == meets(level));
    for (int k = 0; k < level && b.converged; ++k) CHECK_FALSE(meets(k));
  }
}

TEST_CASE("block averaging of NaN and infinite samples: no error to report") {
  // A NaN sample gave an error of 0, "converged" (the rounding clamp took the NaN for 0), and a
  // first sample of inf a NaN mean.
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const std::vector<double>& x : {std::vector<double>{1, 2, nan, 4, 5, 6, 7, 8}, std::vector<double>{inf, 1, 2, 3},
                                       std::vector<double>{1, 2, 3, inf}, std::vector<double>(16, nan)}) {
    double sum = 0;
    for (double v : x) sum += v;
    const BlockAverage b = block_average(x);
    CAPTURE(b.mean);
    CHECK(std::isnan(b.mean) == std::isnan(sum));
    if (!std::isnan(sum)) CHECK(b.mean == sum / static_cast<double>(x.size()));
    CHECK(std::isnan(b.err));
    CHECK_FALSE(b.converged);
    CHECK(b.nans == std::count_if(x.begin(), x.end(), [](double v) { return std::isnan(v); }));
  }
}

TEST_CASE("a streamed stats series keeps no rows: its averages from the time given up front") {
  // A batch run sampled at every step for 1e8 steps held every row (115 bytes a sample) until it
  // was killed for memory, writing nothing.
  StatsWriter kept("", {"x"}), streamed("", {"x"}, 2.0);
  Rng rng(3, 0);
  for (int k = 0; k < 5000; ++k) {
    const std::vector<double> row{rng.normal()};
    kept.add(row, 0.001 * k, k);
    streamed.add(row, 0.001 * k, k);
  }
  CHECK(streamed.rows().empty());
  CHECK(streamed.samples() == 5000);
  CHECK(streamed.last_row() == kept.last_row());
  const BlockAverage a = kept.average(0, 2.0), b = streamed.average(0, 2.0);
  CHECK(b.n == 3000);
  CHECK(b.n == a.n);
  CHECK(b.block == a.block);
  CHECK(b.mean == doctest::Approx(a.mean).epsilon(1e-13));
  CHECK(b.err == doctest::Approx(a.err).epsilon(1e-9));
  CHECK_THROWS_AS(streamed.average(0, 1.0), std::logic_error);
}

TEST_CASE("a stats series given a state restored to an earlier time drops the samples of the abandoned branch") {
  // After `restore`, the shell's stats averaged the samples after the restored time with those
  // the run took again over the same times.
  StatsWriter s("", {"x"});
  for (int k = 0; k <= 20; ++k) s.add({static_cast<double>(k)}, 0.1 * k, 10 * k);
  CHECK(s.drop_after(0.1 * 10, 100) == 10);
  CHECK(s.rows().size() == 11);
  CHECK(s.last_step() == 100);  // the restored step's sample is kept: not taken again
  CHECK(s.average(0, 0.0).mean == doctest::Approx(5.0));
  CHECK(s.drop_after(0.55, 55) == 5);
  CHECK(s.last_step() == -1);  // no sample at that time: the next one is taken
}
