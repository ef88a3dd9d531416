#include "linalg/vector_ops.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <vector>

namespace silt::linalg {
namespace {

int64_t blocks_of(int64_t n) { return (n + kBlock - 1) / kBlock; }

template <class F>
void for_blocks(int64_t n, F&& f) {
  const int64_t nb = blocks_of(n);
  if (nb <= 1) {
    if (n > 0) f(0, int64_t{0}, n);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, nb), [&](const tbb::blocked_range<int64_t>& r) {
    for (int64_t b = r.begin(); b < r.end(); ++b) f(b, b * kBlock, std::min(n, (b + 1) * kBlock));
  });
}

}  // namespace

double dot(const Vector& a, const Vector& b) {
  const int64_t n = a.size();
  std::vector<double> part(static_cast<size_t>(std::max<int64_t>(1, blocks_of(n))), 0.0);
  for_blocks(n, [&](int64_t blk, int64_t lo, int64_t hi) {
    double s = 0;
    for (int64_t i = lo; i < hi; ++i) s += a[i] * b[i];
    part[static_cast<size_t>(blk)] = s;
  });
  double s = 0;
  for (double p : part) s += p;
  return s;
}

void axpy(double alpha, const Vector& x, Vector& y) {
  for_blocks(x.size(), [&](int64_t, int64_t lo, int64_t hi) {
    for (int64_t i = lo; i < hi; ++i) y[i] += alpha * x[i];
  });
}

void xpby(const Vector& z, double beta, Vector& p) {
  for_blocks(z.size(), [&](int64_t, int64_t lo, int64_t hi) {
    for (int64_t i = lo; i < hi; ++i) p[i] = z[i] + beta * p[i];
  });
}

bool all_finite(const Vector& v) {
  for (int64_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

}  // namespace silt::linalg
