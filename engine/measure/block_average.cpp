#include <cmath>

#include "silt/statistics.hpp"

namespace silt {

BlockAverage block_average(const std::vector<double>& x) {
  BlockAverage out;
  out.n = static_cast<int64_t>(x.size());
  if (x.empty()) return out;
  double sum = 0;
  for (double v : x) sum += v;
  out.mean = sum / out.n;
  if (out.n < 2) return out;
  // Naive standard error at each blocking level.
  std::vector<double> data = x;
  std::vector<double> err;
  while (data.size() >= 2) {
    const double m = static_cast<double>(data.size());
    double c0 = 0;
    for (double v : data) c0 += (v - out.mean) * (v - out.mean);
    c0 /= m;
    err.push_back(std::sqrt(c0 / (m - 1)));
    std::vector<double> next(data.size() / 2);
    for (size_t i = 0; i < next.size(); ++i) next[i] = 0.5 * (data[2 * i] + data[2 * i + 1]);
    data.swap(next);
  }
  if (err[0] == 0) {  // constant series
    out.converged = true;
    return out;
  }
  const double n = static_cast<double>(out.n);
  for (size_t k = 0; k < err.size(); ++k) {
    const double b = std::ldexp(1.0, static_cast<int>(k));
    if (b * b * b > 2.0 * n * std::pow(err[k] / err[0], 4)) {
      out.err = err[k];
      out.block = static_cast<int64_t>(b);
      out.converged = true;
      return out;
    }
  }
  // No level satisfies the criterion: report the largest estimate with at least 4 blocks.
  size_t best = 0;
  for (size_t k = 0; k < err.size(); ++k)
    if ((out.n >> k) >= 4 && err[k] > err[best]) best = k;
  out.err = err[best];
  out.block = int64_t{1} << best;
  return out;
}

}  // namespace silt
