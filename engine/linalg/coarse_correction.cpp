// The balancing preconditioner: a Cholesky factor of an earlier matrix, corrected exactly on the
// span of W (silt/linalg.hpp).
#include "linalg/vector_ops.hpp"

namespace silt::linalg {

SolveReport CoarseCorrection::setup(const SparseMatrix& a, SparseMatrix& w, const Preconditioner& m) {
  m_ = &m;
  w_.swap(w);  // Eigen's sparse matrices have no move
  w_.makeCompressed();
  ready_ = false;
  SolveReport rep;
  if (w_.cols() == 0) return rep;
  aw_ = a * w_;
  SparseMatrix e = SparseMatrix(w_.transpose()) * aw_;
  e.makeCompressed();
  // E is symmetric up to round-off (its (c, d) and (d, c) are summed in different orders), and
  // CHOLMOD reads its lower triangle. The diagonal raised by a relative 1e-10 keeps E definite
  // when W's columns are dependent.
  for (int64_t k = 0; k < e.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(e, k); it; ++it)
      if (it.row() == it.col()) it.valueRef() *= 1 + 1e-10;
  rep = e_.factorize(e);
  ready_ = rep.ok();
  return rep;
}

// A enters only through A W, kept from the setup: A Q r = (A W) E^-1 W^T r, and, A being
// symmetric, W^T A z = (A W)^T z. No product with A itself.
void CoarseCorrection::apply(const Vector& r, Vector& z) const {
  if (!ready_) {
    m_->apply(r, z);
    return;
  }
  // ec = E^-1 W^T r, q = W ec = Q r
  c_.noalias() = w_.transpose() * r;
  (void)e_.solve(c_, ec_);
  q_.noalias() = w_ * ec_;
  // z = M^-1 (r - A q)
  y_ = r;
  y_.noalias() -= aw_ * ec_;
  m_->apply(y_, z);
  // z += q - Q A z
  c_.noalias() = aw_.transpose() * z;
  (void)e_.solve(c_, ec_);
  z += q_;
  z.noalias() -= w_ * ec_;
}

}  // namespace silt::linalg
