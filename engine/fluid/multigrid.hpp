// Geometric multigrid for the cell-centred pressure operator A = sigma - Lap_h
// (poisson_kernels.hpp), used as the preconditioner of conjugate gradients (MGPCG; Tatebe 1993,
// McAdams, Sifakis & Teran 2010), and the solver that puts the two together.
//
// The hierarchy: each level halves the cells of every axis of the one above (its cells are the
// unions of 2^dim children, its spacing 2 h), while every axis has an even count of at least 4
// and the level has more than `coarsest_cells` cells. Each level carries its own rediscretised
// operator (the same stencil and boundary conditions with spacing 2 h, and the same sigma).
//
// One application of the preconditioner is one V-cycle from zero. For CG it must be a fixed,
// symmetric positive definite linear map, which the cycle is when
//   - the smoother is symmetric: nu sweeps before the coarse correction and nu after, the
//     second set the adjoint of the first (red-black Gauss-Seidel red then black before, black
//     then red after; or damped Jacobi, self-adjoint), and convergent in the energy norm;
//   - restriction is the scaled transpose of prolongation, R = P^T / 2^dim;
//   - the coarsest solve is symmetric positive definite (a Cholesky solve, or symmetric sweeps).
// Then the error propagation E = S* (I - P A_c^-1 R A) S is self-adjoint in the energy inner
// product with eigenvalues below 1, so M^-1 = (I - E) A^-1 is symmetric positive definite.
//
// The singular case (no Dirichlet face, sigma = 0): the constants are A's null space, and the
// cycle works on the zero-mean vectors: the mean is removed from the residual it is given and
// from the correction it returns; the coarsest solve pins its first cell.
//
// Not re-entrant: one cycle at a time per object (the workspaces are members). No allocation
// after the first cycle (where CHOLMOD sizes its solve workspaces); results do not depend on the number of threads
// (every entry of every level is written by one task, reductions are the fixed-block ones of the linalg layer, CHOLMOD
// serial).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fluid/grid.hpp"
#include "fluid/poisson_operator.hpp"
#include "silt/linalg.hpp"

namespace silt::fluid {

// How a correction on the coarse cells is carried to the fine ones.
enum class Prolongation {
  kConstant,  // each child takes its parent's value; R averages the 2^dim children
  kLinear,    // (bi/tri)linear between coarse centres: weights 3/4, 1/4 per axis (product over axes)
};

// The defaults are the cheapest per solve measured on 32^2 .. 512^2 and 16^3 .. 128^3 boxes
// (CG to 1e-8 in 6-7 iterations on every size): two sweeps make up for the constant
// prolongation's rougher correction, and its transfers cost far less than the linear one's
// 4^dim-point restriction. The linear prolongation needs 7 (two sweeps) or 9-10 (one sweep).
struct MultigridOptions {
  Prolongation prolongation = Prolongation::kConstant;
  int sweeps = 2;                    // smoothing sweeps before, and as many after (at least 1)
  int64_t coarsest_cells = 64;       // coarsening stops at a level of at most this many cells
  int64_t max_direct_cells = 16384;  // the coarsest level is solved by Cholesky up to this size,
  int coarse_sweeps = 30;            // and beyond it by this many symmetric sweeps
};

// Whether the hierarchy halves `g` once more (the rule above); the cells of its coarsest level; and
// "" where that level is solved directly, else what makes it large and which cells would not.
bool coarsens(const Grid& g, const MultigridOptions& opt);
int64_t coarsest_level_cells(const Grid& g, const MultigridOptions& opt = {});
std::string coarsening_note(const Grid& g, const MultigridOptions& opt = {});

class MultigridPreconditioner final : public linalg::Preconditioner {
 public:
  MultigridPreconditioner(const Grid& g, double sigma, const MultigridOptions& opt = {});
  ~MultigridPreconditioner() override;
  MultigridPreconditioner(const MultigridPreconditioner&) = delete;
  MultigridPreconditioner& operator=(const MultigridPreconditioner&) = delete;

  // z = M^-1 r: one V-cycle for A z = r from z = 0.
  void apply(const linalg::Vector& r, linalg::Vector& z) const override;

  int levels() const;
  const Grid& level_grid(int l) const;
  bool singular() const { return singular_; }
  bool direct_coarsest() const { return direct_; }
  // v -= mean(v) in the singular case (A's range), nothing otherwise; a deterministic sum.
  void remove_mean(linalg::Vector& v) const;

 private:
  struct Level;
  void cycle(int l) const;
  void smooth(Level& lv, bool forward) const;
  void coarsest_solve(Level& lv) const;

  MultigridOptions opt_;
  bool singular_ = false;
  bool direct_ = false;
  mutable std::vector<Level> levels_;  // the workspaces of the cycle
  linalg::CholeskyFactor coarse_factor_;
  mutable std::vector<double> block_sums_;  // the mean's partial sums, one per fixed block of cells
};

struct PoissonSolverOptions {
  linalg::SolveOptions cg{1e-8, 200};
  MultigridOptions multigrid;
};

// A p = b by conjugate gradients preconditioned by one V-cycle per iteration. In the singular
// case the mean is removed from b (the part of b outside A's range, which no p can match), from
// the initial guess and from the solution: p is the zero-mean solution. The operator, the
// hierarchy and the right-hand side's copy are built once; conjugate_gradient (linalg) makes its
// own iteration vectors on each call.
class PoissonSolver {
 public:
  explicit PoissonSolver(const Grid& g, double sigma = 0, const PoissonSolverOptions& opt = {});
  // x: the initial guess (zero if it has not the size of the grid), the solution on return.
  linalg::SolveReport solve(const Eigen::Ref<const linalg::Vector>& b, linalg::Vector& x);

  const PoissonOperator& op() const { return op_; }
  const MultigridPreconditioner& preconditioner() const { return mg_; }
  const PoissonSolverOptions& options() const { return opt_; }
  void set_cg_options(const linalg::SolveOptions& o) { opt_.cg = o; }

 private:
  PoissonSolverOptions opt_;
  PoissonOperator op_;
  MultigridPreconditioner mg_;
  linalg::Vector rhs_;  // b without its mean (singular case)
  linalg::CgWorkspace cg_;
};

}  // namespace silt::fluid
