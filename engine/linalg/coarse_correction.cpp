// The balancing preconditioner: a Cholesky factor of an earlier matrix, corrected exactly on the
// span of W (silt/linalg.hpp).
#include "linalg/vector_ops.hpp"

namespace silt::linalg {

SolveReport CoarseCorrection::setup(const SparseMatrix& a, const SparseMatrix& w, const Preconditioner& m) {
  a_ = &a;
  m_ = &m;
  w_ = w;
  w_.makeCompressed();
  ready_ = false;
  SolveReport rep;
  if (w_.cols() == 0) return rep;
  const SparseMatrix aw = a * w_;
  SparseMatrix e = SparseMatrix(w_.transpose()) * aw;
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

void CoarseCorrection::apply(const Vector& r, Vector& z) const {
  if (!ready_) {
    m_->apply(r, z);
    return;
  }
  const SparseOperator a(*a_);
  // q = Q r
  c_ = w_.transpose() * r;
  (void)e_.solve(c_, ec_);
  q_ = w_ * ec_;
  // z = M^-1 (r - A q)
  a.apply(q_, t_);
  y_ = r - t_;
  m_->apply(y_, z);
  // z += q - Q A z
  a.apply(z, t_);
  c_ = w_.transpose() * t_;
  (void)e_.solve(c_, ec_);
  z += q_;
  z -= w_ * ec_;
}

}  // namespace silt::linalg
