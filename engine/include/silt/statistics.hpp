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
  int64_t block = 1;       // samples per block at the chosen level
  bool converged = false;  // false: too few samples for the correlation time (err is a lower bound)
};
BlockAverage block_average(const std::vector<double>& x);

}  // namespace silt
