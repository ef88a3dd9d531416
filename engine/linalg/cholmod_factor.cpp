// The sparse Cholesky factor, on CHOLMOD: the only file of silt that includes cholmod.h and owns
// its handles (the common workspace, the factor, the solve's dense workspaces).
//
// A symmetric matrix stored whole (both triangles) is given to CHOLMOD as a view with stype -1:
// CHOLMOD reads the lower triangle and ignores the upper. The default ordering strategy (AMD, then
// METIS when AMD's fill is high) and a supernodal factorisation are used; both are deterministic,
// and the BLAS under them is OpenBLAS's serial build (scripts/setup.sh), so a factor does not
// depend on the number of threads.
#include <cholmod.h>

#include <cmath>

#include "linalg/supernodal_solve.hpp"
#include "linalg/vector_ops.hpp"

namespace silt::linalg {
namespace {

// A view of `a` (compressed columns), no copy: the lower triangle of a symmetric matrix.
cholmod_sparse view(const SparseMatrix& a) {
  cholmod_sparse s{};
  s.nrow = static_cast<size_t>(a.rows());
  s.ncol = static_cast<size_t>(a.cols());
  s.nzmax = static_cast<size_t>(a.nonZeros());
  s.p = const_cast<int*>(a.outerIndexPtr());
  s.i = const_cast<int*>(a.innerIndexPtr());
  s.x = const_cast<double*>(a.valuePtr());
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

}  // namespace

struct CholeskyFactor::Impl {
  cholmod_common c{};
  cholmod_factor* l = nullptr;
  mutable cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;  // cholmod_solve2's workspaces
  int64_t n = -1, nnz = -1;
  std::vector<int> outer, inner;  // the analysed pattern
  bool factored = false;
  SupernodalSolver tree;    // silt's own solves with the supernodal factor
  bool tree_ready = false;  // planned for the factor held

  Impl() {
    cholmod_start(&c);
    c.supernodal = CHOLMOD_SUPERNODAL;
    c.print = 0;  // failures are reported by silt
    c.error_handler = nullptr;
  }
  ~Impl() {
    if (l) cholmod_free_factor(&l, &c);
    if (x) cholmod_free_dense(&x, &c);
    if (y) cholmod_free_dense(&y, &c);
    if (e) cholmod_free_dense(&e, &c);
    cholmod_finish(&c);
  }

  bool same_pattern(const SparseMatrix& a) const {
    if (a.rows() != n || a.nonZeros() != nnz) return false;
    return std::equal(outer.begin(), outer.end(), a.outerIndexPtr()) &&
           std::equal(inner.begin(), inner.end(), a.innerIndexPtr());
  }
};

namespace {

// `a` itself when its columns are compressed (CHOLMOD's packed form), else a compressed copy.
const SparseMatrix* compressed(const SparseMatrix& a, SparseMatrix& copy) {
  if (a.isCompressed()) return &a;
  copy = a;
  copy.makeCompressed();
  return &copy;
}

}  // namespace

CholeskyFactor::CholeskyFactor() : impl_(std::make_unique<Impl>()) {}
CholeskyFactor::~CholeskyFactor() = default;

void CholeskyFactor::analyze(const SparseMatrix& a0, const std::vector<int>* order) {
  SparseMatrix copy;
  const SparseMatrix* a = compressed(a0, copy);
  Impl& im = *impl_;
  if (im.l) cholmod_free_factor(&im.l, &im.c);
  cholmod_sparse v = view(*a);
  if (order && static_cast<int64_t>(order->size()) == a->rows()) {
    // The given order alone (CHOLMOD checks that it is a permutation), then the default again.
    const int nmethods = im.c.nmethods, first = im.c.method[0].ordering;
    im.c.nmethods = 1;
    im.c.method[0].ordering = CHOLMOD_GIVEN;
    im.l = cholmod_analyze_p(&v, const_cast<int*>(order->data()), nullptr, 0, &im.c);
    im.c.nmethods = nmethods;
    im.c.method[0].ordering = first;
  } else {
    im.l = cholmod_analyze(&v, &im.c);
  }
  im.n = a->rows();
  im.nnz = a->nonZeros();
  im.outer.assign(a->outerIndexPtr(), a->outerIndexPtr() + a->cols() + 1);
  im.inner.assign(a->innerIndexPtr(), a->innerIndexPtr() + a->nonZeros());
  im.factored = false;
  ++analyses_;
}

SolveReport CholeskyFactor::factorize(const SparseMatrix& a0) {
  SparseMatrix copy;
  const SparseMatrix* a = compressed(a0, copy);
  SolveReport rep;
  Impl& im = *impl_;
  im.factored = false;
  for (int64_t k = 0; k < a->nonZeros(); ++k)
    if (!std::isfinite(a->valuePtr()[k])) {
      rep.status = SolveStatus::kNotFinite;
      rep.message = "the matrix has a non-finite entry";
      return rep;
    }
  if (!im.l || !im.same_pattern(*a)) analyze(*a);
  cholmod_sparse v = view(*a);
  cholmod_factorize(&v, im.l, &im.c);
  ++factorizations_;
  if (im.c.status == CHOLMOD_NOT_POSDEF || im.l->minor < im.l->n) {
    rep.status = SolveStatus::kNotPositive;
    // minor counts in the fill-reducing order: Perm gives the matrix's own column.
    const auto* perm = static_cast<const int*>(im.l->Perm);
    const auto minor = static_cast<int64_t>(im.l->minor);
    rep.column = minor < static_cast<int64_t>(im.l->n) ? (perm ? perm[minor] : minor) : -1;
    rep.message = "the matrix is not positive definite (the factorisation failed at column " +
                  std::to_string(rep.column) + " of " + std::to_string(im.l->n) + ")";
    return rep;
  }
  if (im.c.status < CHOLMOD_OK) {
    rep.status = SolveStatus::kNotFinite;
    rep.message = "CHOLMOD failed (status " + std::to_string(im.c.status) + ", out of memory?)";
    return rep;
  }
  im.factored = true;
  im.tree_ready = false;
  if (im.l->is_super && im.l->is_ll && im.l->itype == CHOLMOD_INT && im.l->xtype == CHOLMOD_REAL) {
    SupernodalView sv;
    sv.n = static_cast<int64_t>(im.l->n);
    sv.nsuper = static_cast<int64_t>(im.l->nsuper);
    sv.super = static_cast<const int*>(im.l->super);
    sv.pi = static_cast<const int*>(im.l->pi);
    sv.px = static_cast<const int*>(im.l->px);
    sv.s = static_cast<const int*>(im.l->s);
    sv.x = static_cast<const double*>(im.l->x);
    sv.perm = static_cast<const int*>(im.l->Perm);
    im.tree_ready = im.tree.plan(sv);
    if (im.tree_ready && single_) im.tree.keep_single();
  }
  return rep;
}

bool CholeskyFactor::ready() const { return impl_->factored; }

bool CholeskyFactor::analysed_for(const SparseMatrix& a) const { return impl_->l && impl_->same_pattern(a); }

std::vector<int> CholeskyFactor::order() const {
  const Impl& im = *impl_;
  if (!im.l || !im.l->Perm) return {};
  const auto* perm = static_cast<const int*>(im.l->Perm);
  return {perm, perm + im.l->n};
}

SolveReport CholeskyFactor::solve(const Vector& b, Vector& x) const { return solve(b, x, false); }

void CholeskyFactor::set_single_preconditioner(bool on) {
  if (on == single_) return;
  single_ = on;
  Impl& im = *impl_;
  if (!im.tree_ready) return;
  if (on) im.tree.keep_single();
  else im.tree.drop_single();
}

bool CholeskyFactor::applies_single() const { return impl_->tree_ready && impl_->tree.has_single(); }

SolveReport CholeskyFactor::solve(const Vector& b, Vector& x, bool single) const {
  SolveReport rep;
  if (!ready()) {
    rep.status = SolveStatus::kNotPositive;
    rep.message = "no factor is held (the last factorisation failed or none was made)";
    return rep;
  }
  Impl& im = *impl_;
  if (!all_finite(b)) {
    rep.status = SolveStatus::kNotFinite;
    rep.message = "the right-hand side is not finite";
    return rep;
  }
  if (im.tree_ready && !cholmod_solve_) {
    x.resize(b.size());
    im.tree.solve(b.data(), x.data(), single);
    if (!all_finite(x)) {
      rep.status = SolveStatus::kNotFinite;
      rep.message = "the solution is not finite";
    }
    return rep;
  }
  cholmod_dense bd{};
  bd.nrow = static_cast<size_t>(b.size());
  bd.ncol = 1;
  bd.nzmax = bd.nrow;
  bd.d = bd.nrow;
  bd.x = const_cast<double*>(b.data());
  bd.xtype = CHOLMOD_REAL;
  bd.dtype = CHOLMOD_DOUBLE;
  cholmod_solve2(CHOLMOD_A, im.l, &bd, nullptr, &im.x, nullptr, &im.y, &im.e, &im.c);
  x = Eigen::Map<const Vector>(static_cast<const double*>(im.x->x), b.size());
  if (!all_finite(x)) {
    rep.status = SolveStatus::kNotFinite;
    rep.message = "the solution is not finite";
  }
  return rep;
}

SolveSplit CholeskyFactor::solve_split() const { return impl_->tree_ready ? impl_->tree.split() : SolveSplit{}; }

void CholeskyFactor::apply(const Vector& r, Vector& z) const { (void)solve(r, z, single_); }

int64_t CholeskyFactor::factor_entries() const {
  const Impl& im = *impl_;
  if (!im.l) return 0;
  return im.l->is_super ? static_cast<int64_t>(im.l->xsize) : static_cast<int64_t>(im.c.lnz);
}

int64_t CholeskyFactor::factor_bytes() const {
  const Impl& im = *impl_;
  if (!im.l) return 0;
  // Values (and their copy as floats, when held), plus the integer pattern of a simplicial factor
  // (a supernodal one's is small).
  const int64_t floats = applies_single() ? factor_entries() * static_cast<int64_t>(sizeof(float)) : 0;
  return factor_entries() * static_cast<int64_t>(sizeof(double)) + floats +
         (im.l->is_super ? static_cast<int64_t>(im.l->ssize) * 4 : factor_entries() * 4);
}

namespace {

// The size of a supernodal symbolic factor: its values (the supernodes' rectangles, Lx), its
// integers (Ls, and as many again for where silt's solves update each row; Lpi, Lpx, super, and
// the permutation and column counts of n entries each), and the largest update matrix of a
// supernode (maxcsize) the numerical factorisation works in.
FactorSize size_of(const cholmod_factor* l, int64_t scale) {
  FactorSize f;
  if (!l) return f;
  if (l->is_super) {
    f.entries = static_cast<int64_t>(l->xsize) * scale * scale;
    f.integers = 2 * static_cast<int64_t>(l->ssize) * scale + 3 * static_cast<int64_t>(l->nsuper + 1) +
                 4 * static_cast<int64_t>(l->n) * scale;
    f.update = static_cast<int64_t>(l->maxcsize) * scale * scale;
  } else {
    f.entries = static_cast<int64_t>(l->nzmax) * scale * scale;
    f.integers = static_cast<int64_t>(l->nzmax) * scale * scale + 6 * static_cast<int64_t>(l->n) * scale;
  }
  return f;
}

}  // namespace

FactorSize CholeskyFactor::size() const { return size_of(impl_->l, 1); }

FactorSize block_factor_size(const SparseMatrix& pattern0, int block) {
  SparseMatrix copy;
  const SparseMatrix* pattern = compressed(pattern0, copy);
  cholmod_common c{};
  cholmod_start(&c);
  c.supernodal = CHOLMOD_SUPERNODAL;
  c.print = 0;
  c.error_handler = nullptr;
  cholmod_sparse v = view(*pattern);
  v.xtype = CHOLMOD_PATTERN;
  cholmod_factor* l = cholmod_analyze(&v, &c);
  const FactorSize f = size_of(l, block);
  if (l) cholmod_free_factor(&l, &c);
  cholmod_finish(&c);
  return f;
}

}  // namespace silt::linalg
