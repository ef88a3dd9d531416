// Statistics of time series.
#pragma once

#include <cstdint>
#include <vector>

namespace silt {

// Mean and statistical error of the mean of a correlated series by block averaging
// (Flyvbjerg & Petersen 1989). Blocks of 2^k samples; the block size is the smallest B with
// B^3 > 2 n (s_B / s_1)^4 (Wolff 2004; Lee et al. 2011), s_B the naive error at block size B.
struct BlockAverage {
  double mean = 0;
  double err = 0;
  int64_t n = 0;
  int64_t nans = 0;        // NaN samples among the n (the mean is then NaN)
  int64_t block = 1;       // samples per block at the chosen level
  bool converged = false;  // false: too few samples for the correlation time (err is a lower bound)
};
BlockAverage block_average(const std::vector<double>& x);

// The same block averaging of a series given one value at a time (block_average feeds it the
// series), in memory that grows as the logarithm of its length (a run sampled at every step for
// 1e9 steps): per blocking level, the count of its values and their sums and sums of squares
// (relative to the first value of the series, in long double: a constant series has an error of
// exactly 0, and one far from zero keeps its fluctuations), and its half-formed pair. Level k
// holds the means of pairs of level k - 1 (an odd last one left out).
class BlockAccumulator {
 public:
  void add(double x);
  int64_t count() const { return levels_.empty() ? 0 : levels_[0].m; }
  BlockAverage result() const;

 private:
  struct Level {
    int64_t m = 0;
    long double s1 = 0, s2 = 0;  // sums of (v - x0) and (v - x0)^2
    bool pending = false;
    double half = 0;  // the first of a pair not yet complete
  };
  std::vector<Level> levels_;
  double x0_ = 0;
  long double sum_ = 0;  // of the values themselves
  int64_t nans_ = 0;
};

}  // namespace silt
