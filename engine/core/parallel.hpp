// Parallel loops whose results do not depend on the number of threads.
//
// parallel_for writes disjoint outputs, so any partition gives the same result. Reductions of
// sums go through fixed chunks whose partial results are combined in chunk order; a maximum is
// exact in any order.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <array>
#include <cmath>
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

// The same, each thread of the arena taking the same contiguous share of [0, n) at every call
// (TBB's static partitioner): no share moves between threads, so a thread finds its rows in its
// own caches from one pass to the next, but a thread slowed by the host is not relieved either.
template <class F>
void parallel_for_pinned(int64_t n, int64_t grain, F&& f) {
  if (n <= grain) {
    if (n > 0) f(int64_t{0}, n);
    return;
  }
  tbb::parallel_for(
      tbb::blocked_range<int64_t>(0, n, grain), [&](const tbb::blocked_range<int64_t>& r) { f(r.begin(), r.end()); },
      tbb::static_partitioner{});
}

// a = the maxima of a and b, element by element; a NaN of b replaces, a NaN of a stays.
template <size_t K>
void max_into(std::array<double, K>& a, const std::array<double, K>& b) {
  for (size_t k = 0; k < K; ++k) a[k] = (b[k] > a[k] || std::isnan(b[k])) ? b[k] : a[k];
}

// K maxima over [0, n) of f(begin, end), which returns the maxima of its block as
// std::array<double, K> (0 for an empty range). A NaN of any block stays, whatever the split.
template <size_t K, class F>
std::array<double, K> parallel_max(int64_t n, int64_t grain, F&& f) {
  using A = std::array<double, K>;
  auto join = [](A a, const A& b) {
    max_into(a, b);
    return a;
  };
  if (n <= grain) return n > 0 ? f(int64_t{0}, n) : A{};
  return tbb::parallel_reduce(
      tbb::blocked_range<int64_t>(0, n, grain), A{},
      [&](const tbb::blocked_range<int64_t>& r, const A& m) { return join(m, f(r.begin(), r.end())); }, join);
}

// K sums in one pass: f(begin, end) returns the K partial sums of its chunk (std::array<double, K>),
// over chunks of exactly `chunk` items combined in chunk order. Up to kStackChunks chunks the
// partial sums stay on the stack (these reductions run every step).
inline constexpr int64_t kStackChunks = 64;
template <size_t K, class F>
std::array<double, K> deterministic_sums(int64_t n, int64_t chunk, F&& f) {
  const int64_t nc = std::max<int64_t>((n + chunk - 1) / chunk, 0);
  std::array<std::array<double, K>, kStackChunks> stack_part;
  std::vector<std::array<double, K>> heap_part(nc > kStackChunks ? static_cast<size_t>(nc) : 0);
  std::array<double, K>* part = nc > kStackChunks ? heap_part.data() : stack_part.data();
  parallel_for(nc, 1, [&](int64_t b, int64_t e) {
    for (int64_t c = b; c < e; ++c) part[c] = f(c * chunk, std::min(n, (c + 1) * chunk));
  });
  std::array<double, K> s{};
  for (int64_t c = 0; c < nc; ++c)
    for (size_t k = 0; k < K; ++k) s[k] += part[c][k];
  return s;
}

// Sum over [0, n) of f(begin, end) with chunks of exactly `chunk` items combined in order.
template <class F>
double deterministic_sum(int64_t n, int64_t chunk, F&& f) {
  return deterministic_sums<1>(n, chunk, [&](int64_t b, int64_t e) { return std::array<double, 1>{f(b, e)}; })[0];
}

}  // namespace silt
