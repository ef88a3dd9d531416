// A sparse matrix product row by row (each row by one thread, in a fixed order within the row),
// and the Jacobi preconditioner. The matrices are symmetric: row i is column i of the compressed
// columns, read in place.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "linalg/vector_ops.hpp"

namespace silt::linalg {

SparseOperator::SparseOperator(const SparseMatrix& a) : a_(a) {}

void SparseOperator::apply(const Vector& x, Vector& y) const {
  const int64_t n = a_.cols();
  y.resize(n);
  const int* outer = a_.outerIndexPtr();
  const int* inner = a_.innerIndexPtr();
  const double* val = a_.valuePtr();
  const int* counts = a_.innerNonZeroPtr();  // null when compressed
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, n, 1024), [&](const tbb::blocked_range<int64_t>& r) {
    const double* xv = x.data();
    for (int64_t i = r.begin(); i < r.end(); ++i) {
      // Four sums, entries k, k + 1, k + 2, k + 3 into each in turn, then (s0 + s1) + (s2 + s3)
      // and the rest: four chains of additions instead of one, the same order on any thread.
      double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
      const int begin = outer[i], end = counts ? begin + counts[i] : outer[i + 1];
      int k = begin;
      for (; k + 4 <= end; k += 4) {
        s0 += val[k] * xv[inner[k]];
        s1 += val[k + 1] * xv[inner[k + 1]];
        s2 += val[k + 2] * xv[inner[k + 2]];
        s3 += val[k + 3] * xv[inner[k + 3]];
      }
      double s = (s0 + s1) + (s2 + s3);
      for (; k < end; ++k) s += val[k] * xv[inner[k]];
      y[i] = s;
    }
  });
}

JacobiPreconditioner::JacobiPreconditioner(const SparseMatrix& a) : inv_diag_(a.rows()) {
  const Vector d = a.diagonal();
  for (int64_t i = 0; i < d.size(); ++i) inv_diag_[i] = d[i] > 0 ? 1 / d[i] : 1.0;
}

void JacobiPreconditioner::apply(const Vector& r, Vector& z) const { z = r.cwiseProduct(inv_diag_); }

}  // namespace silt::linalg
