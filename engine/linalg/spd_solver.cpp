// The sequence of solves of a time stepper: CG with a Jacobi preconditioner, CG preconditioned by
// a Cholesky factor of an earlier matrix (refactorised when it no longer helps enough), or a
// direct solve every time.
#include <algorithm>
#include <cmath>
#include <limits>

#include "linalg/vector_ops.hpp"

namespace silt::linalg {
namespace {

// The held factor applied exactly (its solve() in double), whatever apply() reads.
class ExactFactor final : public Preconditioner {
 public:
  explicit ExactFactor(const CholeskyFactor& f) : f_(f) {}
  void apply(const Vector& r, Vector& z) const override { (void)f_.solve(r, z); }

 private:
  const CholeskyFactor& f_;
};

}  // namespace

const char* status_name(SolveStatus s) {
  switch (s) {
    case SolveStatus::kConverged: return "converged";
    case SolveStatus::kMaxIterations: return "max_iterations";
    case SolveStatus::kNotPositive: return "not_positive_definite";
    case SolveStatus::kNotFinite: return "not_finite";
    case SolveStatus::kStagnated: return "stagnated";
  }
  return "?";
}

const char* method_name(Method m) {
  switch (m) {
    case Method::kCg: return "cg";
    case Method::kFactorPcg: return "factor_pcg";
    case Method::kDirect: return "direct";
  }
  return "?";
}

SpdSolver::SpdSolver(SolverSettings s) : s_(s) { factor_.set_single_preconditioner(s_.single_factor); }
SpdSolver::~SpdSolver() = default;

void SpdSolver::forget_factor() { factor_valid_ = false; }

SolveReport SpdSolver::restore_factor(const SparseMatrix& source, int solves_since_factor) {
  SolveReport f = factor_.factorize(source);
  factor_valid_ = f.ok();
  solves_since_factor_ = solves_since_factor;
  return f;
}

SolveReport SpdSolver::solve(const SparseMatrix& a, const Vector& b, Vector& x, bool pattern_changed) {
  const double big = b.size() > 0 ? b.cwiseAbs().maxCoeff() : 0.0;
  last_exponent_ = 0;
  if (!(big > 0) || big >= 0x1p-200) return solve_scaled(a, b, x, pattern_changed);
  // 2^e times b (and x) with its largest entry in [1, 2): each entry scaled exactly (ldexp, no
  // power of two formed, which 2^1074 would not be); x back by 2^-e, exactly but where the
  // solution itself falls below a double's range.
  const int e = -std::ilogb(big);
  last_exponent_ = e;
  auto scale = [](const Vector& v, int by) {
    return Vector(v.unaryExpr([by](double y) { return std::ldexp(y, by); }));
  };
  const Vector bs = scale(b, e);
  Vector xs = scale(x, e);
  SolveReport rep = solve_scaled(a, bs, xs, pattern_changed);
  x = scale(xs, -e);
  return rep;
}

SolveReport SpdSolver::solve_scaled(const SparseMatrix& a, const Vector& b, Vector& x, bool pattern_changed) {
  const SparseOperator op(a);
  last_m_ = nullptr;
  cg_.z_of_r = false;
  if (s_.method == Method::kCg) {
    // A diagonal entry that is not positive makes the matrix not positive definite at that unknown
    // (nothing resists it), which CG would find, if at all, only as a NaN or a breakdown: named
    // here, as a factorisation names the column where it fails.
    const JacobiPreconditioner jacobi(a);
    if (const int64_t i = jacobi.first_bad(); i >= 0) {
      const double d = jacobi.first_bad_value();
      SolveReport rep;
      rep.status = std::isfinite(d) ? SolveStatus::kNotPositive : SolveStatus::kNotFinite;
      rep.column = rep.status == SolveStatus::kNotPositive ? i : -1;
      rep.message = "diagonal entry " + std::to_string(i) + " is " + std::to_string(d);
      return rep;
    }
    return conjugate_gradient(op, b, x, s_.options, &jacobi, &cg_);
  }
  if (s_.method == Method::kDirect) {
    SolveReport rep = factor_.factorize(a);
    factor_valid_ = false;
    if (!rep.ok()) return rep;
    rep = factor_.solve(b, x);
    if (!rep.ok()) return rep;
    // A factor of a nearly singular matrix solves it inaccurately (CHOLMOD's pivots stay positive
    // while the residual is of order one): past the tolerance a failure, as CG's is (a residual
    // of 1.6 went into the velocities unremarked).
    // Iterative refinement with the same factor: a few solves of the residual's equation take the
    // residual to round-off of b where one solve leaves a few ulps more (1.05e-15 against a
    // tolerance of 1e-15, the lowest the key takes).
    Vector ax, r, dx;
    op.apply(x, ax);
    const double bn = b.norm();
    rep.residual = bn > 0 ? (b - ax).norm() / bn : 0;
    for (int k = 0; k < 3 && bn > 0 && !(rep.residual <= s_.options.tolerance) && std::isfinite(rep.residual); ++k) {
      r = b - ax;
      if (!factor_.solve(r, dx).ok()) break;
      const Vector refined = x + dx;
      op.apply(refined, ax);
      const double residual = (b - ax).norm() / bn;
      if (!(residual < rep.residual)) break;  // it no longer lowers it
      x = refined;
      rep.residual = residual;
    }
    if (!(rep.residual <= s_.options.tolerance)) {
      rep.status = std::isfinite(rep.residual) ? SolveStatus::kMaxIterations : SolveStatus::kNotFinite;
      rep.message = "the direct solve left a relative residual of " + std::to_string(rep.residual) +
                    ": the matrix is numerically singular";
    }
    return rep;
  }
  // kFactorPcg.
  if (pattern_changed) factor_valid_ = false;
  if (s_.refactor_every > 0 && solves_since_factor_ >= s_.refactor_every) factor_valid_ = false;
  auto refactor = [&]() {
    SparseMatrix source;
    if (factor_source) source = factor_source();
    const SparseMatrix& m = factor_source ? source : a;
    SolveReport f = factor_.factorize(m);
    factor_valid_ = f.ok();
    solves_since_factor_ = 0;
    if (factor_valid_ && on_factor) on_factor(m);
    return f;
  };
  if (!factor_valid_)
    if (SolveReport f = refactor(); !f.ok()) return f;
  // The coarse correction of the directions the factor misses first, when the caller has them
  // and they are few: past a quarter of the unknowns, E costs about what a new factor would (and
  // W's columns are likely dependent), so the factor serves alone.
  const Preconditioner* m = &factor_;
  coarse_columns_ = 0;
  if (coarse_space) {
    CoarseSpace space = coarse_space();
    const int64_t columns = space.w.cols();
    const std::vector<int64_t>* keys = space.keys.empty() ? nullptr : &space.keys;
    coarse_.set_drop(s_.coarse_drop);
    if (columns > 0 && 4 * columns <= a.rows() && coarse_.setup(a, space.w, factor_, keys).ok()) {
      m = &coarse_;
      coarse_columns_ = columns;
    }
  }
  // A stale or corrected factor gets a few times the threshold; past that, or on a failure, the
  // solve again from where it got to with a fresh factor of this matrix, alone (a coarse space
  // whose columns are nearly dependent can spoil the correction). A solve that converged but took
  // more than the threshold asks for a fresh factor next time.
  // A fresh factor applied in single precision gets the threshold itself: past it, the rounding of
  // the factor is what matters, and the solve goes on in double (below).
  const bool stale = solves_since_factor_ > 0, corrected = m == &coarse_;
  const int threshold = std::max(1, s_.refactor_iterations);
  SolveOptions first = s_.options;
  if (stale || corrected) first.max_iterations = std::min(first.max_iterations, 4 * threshold);
  else if (factor_.applies_single()) first.max_iterations = std::min(first.max_iterations, threshold);
  SolveReport rep = conjugate_gradient(op, b, x, first, m, &cg_);
  last_m_ = m;
  ++solves_since_factor_;
  // The solve again from where `so_far` left it, preconditioned by p, for what is left of its
  // iterations (options.max_iterations bounds the whole solve) and at most `cap`; a failure's
  // message names both parts (`how`: what the first part used, then the second).
  auto go_on = [&](const SolveReport& so_far, const Preconditioner* p, int cap, const char* how) {
    const int spent = so_far.iterations;
    if (!all_finite(x)) x.setZero();
    SolveOptions rest = s_.options;
    rest.max_iterations = std::min(cap, std::max(0, s_.options.max_iterations - spent));
    SolveReport r = conjugate_gradient(op, b, x, rest, p, &cg_);
    last_m_ = &factor_;  // (or its exact application, which the estimate need not be)
    r.iterations += spent;
    if (r.status == SolveStatus::kMaxIterations && r.iterations >= s_.options.max_iterations)
      r.message = "no convergence in " + std::to_string(s_.options.max_iterations) + " iterations (" +
                  std::to_string(spent) + how + "; relative residual " + std::to_string(r.residual) + ", tolerance " +
                  std::to_string(s_.options.tolerance) + ")";
    return r;
  };
  if (!rep.ok() && (corrected || (stale && rep.status != SolveStatus::kNotFinite))) {
    if (stale)
      if (SolveReport f = refactor(); !f.ok()) return f;
    rep = go_on(rep, &factor_, factor_.applies_single() ? threshold : std::numeric_limits<int>::max(),
                " with the old factor, then a fresh one");
    coarse_columns_ = 0;
    ++solves_since_factor_;
  } else if (rep.iterations > s_.refactor_iterations) {
    factor_valid_ = false;
  }
  // A factor applied in single precision that still leaves the solve short (a matrix so badly
  // conditioned that the rounding of its factor matters) is applied in double for what is left;
  // its floats are kept for the next solve: each solve decides from its factor alone.
  if (!rep.ok() && rep.status != SolveStatus::kNotFinite && factor_.applies_single()) {
    const ExactFactor exact(factor_);
    rep = go_on(rep, &exact, std::numeric_limits<int>::max(), " with the factor in single precision, then in double");
    ++double_retries_;
  }
  return rep;
}

void SpdSolver::error_estimate(const SparseMatrix& a, const Vector& b, const Vector& x, Vector& dx) {
  if (s_.method == Method::kDirect) {
    dx = Vector::Zero(x.size());
    return;
  }
  // dx = M^-1 r, then times the length along it that best cancels r, (dx . r) / (dx . a dx): the
  // step CG would take from x along dx. M^-1 r alone is the error only where M is a; a factor of an
  // earlier matrix applied after the viscosity changed 1e6 times (a packing restored into another
  // liquid) is as good a preconditioner, but read the stress's error 1e6 times over, and Jacobi's
  // diagonal reads the error of the softest directions low.
  const bool of_cg = cg_.z_of_r && cg_.z.size() == x.size() && cg_.r.size() == x.size();
  const Vector* r = &cg_.r;
  if (of_cg) {  // of the x solved, z and r scaled as its b was (the length is the same)
    dx = cg_.z;
  } else {
    SparseOperator(a).apply(x, estimate_r_);
    estimate_r_ = b - estimate_r_;
    r = &estimate_r_;
    if (last_m_) {
      last_m_->apply(estimate_r_, dx);
    } else {
      const JacobiPreconditioner jacobi(a);
      jacobi.apply(estimate_r_, dx);
    }
  }
  SparseOperator(a).apply(dx, estimate_ad_);
  const double curvature = dot(dx, estimate_ad_), along = dot(dx, *r);
  const double length = curvature > 0 && std::isfinite(curvature) && std::isfinite(along) ? along / curvature : 1.0;
  const int e = of_cg ? -last_exponent_ : 0;
  dx = dx.unaryExpr([length, e](double y) { return std::ldexp(y * length, e); });
}

}  // namespace silt::linalg
