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
    for (int64_t i = r.begin(); i < r.end(); ++i) {
      double s = 0;
      const int end = counts ? outer[i] + counts[i] : outer[i + 1];
      for (int k = outer[i]; k < end; ++k) s += val[k] * x[inner[k]];
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
