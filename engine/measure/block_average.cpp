#include <algorithm>
#include <cmath>
#include <limits>

#include "silt/statistics.hpp"

namespace silt {

namespace {

// The level whose error block averaging reports (Wolff's criterion), from the naive standard
// errors of the levels (err[k]: blocks of 2^k samples; at least one level).
void choose_block(BlockAverage& out, const std::vector<double>& err) {
  if (err[0] == 0) {  // constant series
    out.converged = true;
    return;
  }
  const double n = static_cast<double>(out.n);
  for (size_t k = 0; k < err.size(); ++k) {
    const double b = std::ldexp(1.0, static_cast<int>(k));
    if (b * b * b > 2.0 * n * std::pow(err[k] / err[0], 4)) {
      out.err = err[k];
      out.block = static_cast<int64_t>(b);
      out.converged = true;
      return;
    }
  }
  // No level satisfies the criterion: report the largest estimate with at least 4 blocks.
  size_t best = 0;
  for (size_t k = 0; k < err.size(); ++k)
    if ((out.n >> k) >= 4 && err[k] > err[best]) best = k;
  out.err = err[best];
  out.block = int64_t{1} << best;
}

}  // namespace

BlockAverage block_average(const std::vector<double>& x) {
  BlockAccumulator acc;
  for (double v : x) acc.add(v);
  return acc.result();
}

void BlockAccumulator::add(double x) {
  if (std::isnan(x)) ++nans_;
  if (levels_.empty()) x0_ = x;
  sum_ += x;
  double v = x;
  for (size_t k = 0;; ++k) {
    if (k == levels_.size()) levels_.emplace_back();
    Level& l = levels_[k];
    ++l.m;
    const long double d = static_cast<long double>(v) - x0_;
    l.s1 += d;
    l.s2 += d * d;
    if (!l.pending) {
      l.pending = true;
      l.half = v;
      return;
    }
    l.pending = false;
    v = 0.5 * (l.half + v);  // block_average's next level
  }
}

BlockAverage BlockAccumulator::result() const {
  BlockAverage out;
  out.n = count();
  out.nans = nans_;
  if (out.n == 0) return out;
  // The mean from the plain sum (an infinite or NaN sample makes it so, as block_average's);
  // the spreads from the sums relative to the first sample.
  out.mean = static_cast<double>(sum_ / static_cast<long double>(out.n));
  if (out.n < 2) return out;
  const long double shift = std::isfinite(out.mean) ? static_cast<long double>(out.mean) - x0_
                                                    : std::numeric_limits<long double>::quiet_NaN();
  std::vector<double> err;
  for (const Level& l : levels_) {
    if (l.m < 2) break;
    const long double m = static_cast<long double>(l.m);
    long double c0 = (l.s2 - 2 * shift * l.s1 + m * shift * shift) / m;
    if (c0 < 0) c0 = 0;  // rounding (a NaN stays one: no error to report, as block_average's)
    err.push_back(static_cast<double>(std::sqrt(c0 / (m - 1))));
  }
  choose_block(out, err);
  return out;
}

}  // namespace silt
