// Parallel loops whose results do not depend on the number of threads.
//
// parallel_for writes disjoint outputs, so any partition gives the same result. Reductions of
// sums go through fixed chunks whose partial results are combined in chunk order; a maximum is
// exact in any order.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace silt {

// f(begin, end) over [0, n) in blocks of at least `grain`.
template <class F>
void parallel_for(int64_t n, int64_t grain, F&& f) {
  if (n <= grain) {
    if (n > 0) f(int64_t{0}, n);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, n, grain),
                    [&](const tbb::blocked_range<int64_t>& r) { f(r.begin(), r.end()); });
}

// max over [0, n) of f(begin, end) (each block returns its own maximum).
template <class F>
double parallel_max(int64_t n, int64_t grain, F&& f) {
  if (n <= grain) return n > 0 ? f(int64_t{0}, n) : 0.0;
  return tbb::parallel_reduce(
      tbb::blocked_range<int64_t>(0, n, grain), 0.0,
      [&](const tbb::blocked_range<int64_t>& r, double m) { return std::max(m, f(r.begin(), r.end())); },
      [](double a, double b) { return std::max(a, b); });
}

// Sum over [0, n) of f(begin, end) with chunks of exactly `chunk` items combined in order.
template <class F>
double deterministic_sum(int64_t n, int64_t chunk, F&& f) {
  const int64_t nc = (n + chunk - 1) / chunk;
  std::vector<double> part(static_cast<size_t>(std::max<int64_t>(nc, 0)), 0.0);
  parallel_for(nc, 1, [&](int64_t b, int64_t e) {
    for (int64_t c = b; c < e; ++c) part[c] = f(c * chunk, std::min(n, (c + 1) * chunk));
  });
  double s = 0;
  for (double p : part) s += p;
  return s;
}

// K sums in one pass: f(begin, end) returns the K partial sums of its chunk (std::array<double, K>);
// chunks are combined in order, as in deterministic_sum.
template <size_t K, class F>
std::array<double, K> deterministic_sums(int64_t n, int64_t chunk, F&& f) {
  const int64_t nc = (n + chunk - 1) / chunk;
  std::vector<std::array<double, K>> part(static_cast<size_t>(std::max<int64_t>(nc, 0)));
  parallel_for(nc, 1, [&](int64_t b, int64_t e) {
    for (int64_t c = b; c < e; ++c) part[c] = f(c * chunk, std::min(n, (c + 1) * chunk));
  });
  std::array<double, K> s{};
  for (const auto& p : part)
    for (size_t k = 0; k < K; ++k) s[k] += p[k];
  return s;
}

}  // namespace silt
