// Conjugate gradients (Hestenes & Stiefel 1952), preconditioned: the textbook recurrence, with
// the residual recomputed from its definition at the end so that the report is the true one.
#include <cmath>

#include "linalg/vector_ops.hpp"

namespace silt::linalg {
namespace {

// The true relative residual |b - A x| / |b|, with ax as scratch.
double relative_residual(const LinearOperator& a, const Vector& b, const Vector& x, double b_norm, Vector& ax) {
  a.apply(x, ax);
  ax = b - ax;
  const double r = std::sqrt(dot(ax, ax));
  return b_norm > 0 ? r / b_norm : r;
}

}  // namespace

SolveReport conjugate_gradient(const LinearOperator& a, const Vector& b, Vector& x, const SolveOptions& opt,
                               const Preconditioner* m, CgWorkspace* ws) {
  SolveReport rep;
  if (ws) ws->z_of_r = false;  // (z is M^-1 of the residual of the x it updates, the recurrence's)
  const int64_t n = a.size();
  if (x.size() != n) x = Vector::Zero(n);
  if (!all_finite(b) || !all_finite(x)) {
    rep.status = SolveStatus::kNotFinite;
    rep.message = "the right-hand side or the initial guess is not finite";
    return rep;
  }
  const double b_norm = std::sqrt(dot(b, b));
  if (b_norm == 0) {
    x.setZero();
    return rep;
  }
  CgWorkspace local;
  CgWorkspace& w = ws ? *ws : local;
  for (Vector* v : {&w.r, &w.z, &w.p, &w.ap})
    if (v->size() != n) v->resize(n);
  Vector &r = w.r, &z = w.z, &p = w.p, &ap = w.ap;
  auto precondition = [&] {
    if (m) m->apply(r, z);
    else z = r;
    w.z_of_r = true;
  };
  const double target = opt.tolerance * b_norm;
  // The recurrence's residual drifts from the true one on ill-conditioned systems: when it says
  // converged, the true residual is computed and, if it is still above the target, CG restarts
  // from it (residual replacement), a few times at most.
  for (int restart = 0; restart < 4; ++restart) {
    a.apply(x, ap);
    r = b - ap;
    double r_norm = std::sqrt(dot(r, r));
    // A guess farther from the solution than zero (velocities solved under a viscosity 1e60 times
    // lower): its residual is cancelled to the round-off of the guess, not of the solution, which
    // may be orders of magnitude smaller. Zero then.
    if (restart == 0 && r_norm > b_norm) {
      x.setZero();
      r = b;
      r_norm = b_norm;
    }
    if (r_norm <= target || rep.status != SolveStatus::kConverged) break;
    precondition();
    p = z;
    double rz = dot(r, z);
    while (r_norm > target) {
      if (rep.iterations >= opt.max_iterations) {
        rep.status = SolveStatus::kMaxIterations;
        break;
      }
      a.apply(p, ap);
      const double pap = dot(p, ap);
      if (!std::isfinite(pap) || !std::isfinite(rz)) {
        rep.status = SolveStatus::kNotFinite;
        rep.message = "a non-finite value appeared at iteration " + std::to_string(rep.iterations);
        return rep;
      }
      if (pap <= 0 || rz <= 0) {
        rep.status = SolveStatus::kNotPositive;
        rep.message = std::string(pap <= 0 ? "the operator" : "the preconditioner") +
                      " is not positive definite (p.Ap = " + std::to_string(pap) + ", r.z = " + std::to_string(rz) +
                      " at iteration " + std::to_string(rep.iterations) + ")";
        break;
      }
      const double alpha = rz / pap;
      axpy(alpha, p, x);
      axpy(-alpha, ap, r);
      precondition();
      const double rz_next = dot(r, z);
      xpby(z, rz_next / rz, p);
      rz = rz_next;
      r_norm = std::sqrt(dot(r, r));
      ++rep.iterations;
    }
  }
  rep.residual = relative_residual(a, b, x, b_norm, ap);
  if (!std::isfinite(rep.residual)) {
    rep.status = SolveStatus::kNotFinite;
    rep.message = "the solution is not finite";
  } else if (rep.status == SolveStatus::kConverged && rep.residual > opt.tolerance) {
    rep.status = SolveStatus::kStagnated;
    rep.message = "the residual stagnated at " + std::to_string(rep.residual) + " (tolerance " +
                  std::to_string(opt.tolerance) + "): below what round-off allows for this system";
  } else if (rep.status == SolveStatus::kMaxIterations) {
    rep.message = "no convergence in " + std::to_string(opt.max_iterations) + " iterations (relative residual " +
                  std::to_string(rep.residual) + ", tolerance " + std::to_string(opt.tolerance) + ")";
  }
  return rep;
}

}  // namespace silt::linalg
