// The multigrid V-cycle and the MGPCG solver; multigrid.hpp states the conditions that make the
// cycle a symmetric positive definite preconditioner, and this file keeps to them.
#include "fluid/multigrid.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "linalg/vector_ops.hpp"

namespace silt::fluid {

using linalg::Vector;

namespace {

// A short list of (index, weight) along one axis: the coarse parents of a fine cell, or the
// fine children of a coarse cell. Entries with the same index are merged.
struct Taps {
  int count = 0;
  std::array<int64_t, 4> idx{};
  std::array<double, 4> w{};
  void add(int64_t i, double weight) {
    for (int t = 0; t < count; ++t)
      if (idx[t] == i) {
        w[t] += weight;
        return;
      }
    idx[count] = i;
    w[count] = weight;
    ++count;
  }
};

// The 1D prolongation from nc = nf / 2 coarse cells to nf fine ones along one axis. Fine cell
// f = 2 I + s lies a quarter of a coarse cell from the centre of its parent I, towards the
// neighbour J = I - 1 (s = 0) or I + 1 (s = 1): linear interpolation gives 3/4 p_I + 1/4 p_J.
// Beyond the box, p_J is the coarse ghost of the pressure condition: the opposite cell
// (periodic), p_I (Neumann: the fine value is p_I), or -p_I (Dirichlet: p = 0 on the face,
// which is the fine cell's face too, and the fine value is p_I / 2).
std::vector<Taps> prolongation_1d(int64_t nf, const std::array<PressureBc, 2>& bc, Prolongation kind) {
  const int64_t nc = nf / 2;
  std::vector<Taps> up(static_cast<size_t>(nf));
  for (int64_t f = 0; f < nf; ++f) {
    Taps& t = up[static_cast<size_t>(f)];
    const int64_t parent = f / 2;
    if (kind == Prolongation::kConstant) {
      t.add(parent, 1.0);
      continue;
    }
    const int side = static_cast<int>(f % 2);
    const int64_t nb = side ? parent + 1 : parent - 1;
    t.add(parent, 0.75);
    if (nb >= 0 && nb < nc) t.add(nb, 0.25);
    else if (bc[side] == PressureBc::kPeriodic) t.add((nb + nc) % nc, 0.25);
    else t.add(parent, bc[side] == PressureBc::kNeumann ? 0.25 : -0.25);
  }
  return up;
}

// Its transpose: for each coarse cell, the fine cells it feeds and with what weight.
std::vector<Taps> transpose_1d(const std::vector<Taps>& up, int64_t nc) {
  std::vector<Taps> down(static_cast<size_t>(nc));
  for (size_t f = 0; f < up.size(); ++f)
    for (int t = 0; t < up[f].count; ++t)
      down[static_cast<size_t>(up[f].idx[t])].add(static_cast<int64_t>(f), up[f].w[t]);
  return down;
}

// The tensor product of three 1D lists applied to a flat array of dims m (x fastest):
// sum over the taps of tx w_x ty w_y tz w_z src[ix + m0 (iy + m1 iz)].
inline double tensor_sum(const Taps& tx, const Taps& ty, const Taps& tz, const std::array<int64_t, 3>& m,
                         const double* src) {
  double s = 0;
  for (int c = 0; c < tz.count; ++c)
    for (int b = 0; b < ty.count; ++b) {
      const double wyz = ty.w[b] * tz.w[c];
      const int64_t row = m[0] * (ty.idx[b] + m[1] * tz.idx[c]);
      for (int a = 0; a < tx.count; ++a) s += tx.w[a] * wyz * src[row + tx.idx[a]];
    }
  return s;
}

// Whether the red-black colouring ((i + j + k) even or odd) leaves no two neighbours of one
// colour: it fails only across a periodic box of an odd count above 1.
bool red_black_valid(const PoissonStencil& s) {
  for (int a = 0; a < s.dim; ++a)
    if (s.bc[a][0] == PressureBc::kPeriodic && s.n[a] > 1 && s.n[a] % 2 == 1) return false;
  return true;
}

}  // namespace

struct MultigridPreconditioner::Level {
  Grid grid;
  PoissonStencil s;
  bool red_black = true;
  Vector inv_diag;  // 1 / A_cc
  Vector x, b, r;   // the correction, the right-hand side, the residual (or a copy of b)
  Vector tmp;       // damped Jacobi's new iterate (when red-black does not apply)
  // The transfers between this level and the next coarser one, per axis.
  std::array<std::vector<Taps>, 3> up, down;
};

bool coarsens(const Grid& g, const MultigridOptions& opt) {
  bool coarsen = g.cells() > opt.coarsest_cells;
  for (int a = 0; a < g.dim; ++a) coarsen = coarsen && g.n[a] % 2 == 0 && g.n[a] >= 4;
  return coarsen;
}

int64_t coarsest_level_cells(const Grid& g, const MultigridOptions& opt) {
  Grid cur = g;
  while (coarsens(cur, opt))
    for (int a = 0; a < cur.dim; ++a) cur.n[a] /= 2;
  return cur.cells();
}

std::string coarsening_note(const Grid& g, const MultigridOptions& opt) {
  const int64_t coarsest = coarsest_level_cells(g, opt);
  if (coarsest <= opt.max_direct_cells) return "";
  // The nearest counts with one power of two as a common factor whose coarsest level is solved
  // (each axis alone left [4001, 7] at [4096, 7], which does not coarsen either).
  std::string counts;
  for (int64_t q = 2; q <= (int64_t{1} << 20) && counts.empty(); q *= 2) {
    Grid c = g;
    for (int a = 0; a < g.dim; ++a)
      c.n[a] = std::max<int64_t>(1, std::llround(static_cast<double>(g.n[a]) / static_cast<double>(q))) * q;
    if (coarsest_level_cells(c, opt) > opt.max_direct_cells) continue;
    for (int a = 0; a < g.dim; ++a) counts += (a ? ", " : "") + std::to_string(c.n[a]);
  }
  return "the multigrid levels halve every axis while its count is even, and this grid's coarsest has " +
         std::to_string(coarsest) + " cells, too many to solve (above " + std::to_string(opt.max_direct_cells) +
         "): it is smoothed, and CG needs many iterations; " +
         (counts.empty() ? std::string()
                         : "cells with a power of two as a factor, such as [" + counts + "], coarsen, or ") +
         "give fluid.projection = \"fft\"";
}

MultigridPreconditioner::MultigridPreconditioner(const Grid& g, double sigma, const MultigridOptions& opt)
    : opt_(opt), singular_(poisson_singular(g, sigma)) {
  Grid cur = g;
  for (;;) {
    Level lv;
    lv.grid = cur;
    lv.s = make_poisson_stencil(cur, sigma);
    lv.red_black = red_black_valid(lv.s);
    const int64_t n = lv.s.cells();
    lv.inv_diag.resize(n);
    for_each_row(lv.s.n, [&](int64_t j, int64_t k) {
      for (int64_t i = 0; i < lv.s.n[0]; ++i)
        lv.inv_diag[i + lv.s.stride[1] * j + lv.s.stride[2] * k] = 1 / poisson_diagonal_at(lv.s, i, j, k);
    });
    lv.x = Vector::Zero(n);
    lv.b = Vector::Zero(n);
    lv.r = Vector::Zero(n);
    if (!lv.red_black) lv.tmp = Vector::Zero(n);
    const bool coarsen = coarsens(cur, opt_);
    if (coarsen) {
      for (int a = 0; a < 3; ++a) {
        if (a < cur.dim) {
          lv.up[a] = prolongation_1d(cur.n[a], lv.s.bc[a], opt_.prolongation);
          cur.n[a] /= 2;
          cur.h[a] *= 2;
        } else {
          lv.up[a].assign(1, Taps{});
          lv.up[a][0].add(0, 1.0);
        }
        lv.down[a] = transpose_1d(lv.up[a], cur.n[a]);
      }
    }
    levels_.push_back(std::move(lv));
    if (!coarsen) break;
  }
  // The coarsest level: a Cholesky factor when small enough (its first cell pinned when A is
  // singular), else symmetric sweeps.
  const Level& last = levels_.back();
  direct_ = last.s.cells() <= opt_.max_direct_cells;
  if (direct_) direct_ = coarse_factor_.factorize(assemble_poisson(last.grid, sigma, singular_)).ok();
  block_sums_.assign(static_cast<size_t>((g.cells() + linalg::kBlock - 1) / linalg::kBlock), 0.0);
}

MultigridPreconditioner::~MultigridPreconditioner() = default;

int MultigridPreconditioner::levels() const { return static_cast<int>(levels_.size()); }

const Grid& MultigridPreconditioner::level_grid(int l) const { return levels_[static_cast<size_t>(l)].grid; }

// The sum is taken in the fixed blocks of the linalg layer's reductions, each block in order and
// then the blocks in order, whatever the threads.
void MultigridPreconditioner::remove_mean(Vector& v) const {
  if (!singular_) return;
  const int64_t n = v.size();
  const auto blocks = static_cast<int64_t>(block_sums_.size());
  silt::parallel_for(blocks, 1, [&](int64_t begin, int64_t end) {
    for (int64_t blk = begin; blk < end; ++blk) {
      double s = 0;
      for (int64_t i = blk * linalg::kBlock; i < std::min(n, (blk + 1) * linalg::kBlock); ++i) s += v[i];
      block_sums_[static_cast<size_t>(blk)] = s;
    }
  });
  double sum = 0;
  for (double s : block_sums_) sum += s;
  const double mean = sum / static_cast<double>(n);
  silt::parallel_for(n, linalg::kBlock, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) v[i] -= mean;
  });
}

// One symmetric half of a smoothing sweep. Red-black Gauss-Seidel: `forward` updates the red
// cells ((i + j + k) even) then the black ones, backward the reverse, its adjoint. The cells of
// one colour have neighbours of the other colour only, so their updates are independent and the
// result is that of a serial sweep whatever the threads. Damped Jacobi (omega = 4/5 in 2D, 6/7 in
// 3D, the smoothing optimum for the 5- and 7-point Laplacians, below the stability bound 1 set by
// the spectrum of D^-1 A in [0, 2]) is its own adjoint.
void MultigridPreconditioner::smooth(Level& lv, bool forward) const {
  const PoissonStencil& s = lv.s;
  const double* b = lv.b.data();
  const double* inv_diag = lv.inv_diag.data();
  double* x = lv.x.data();
  if (lv.red_black) {
    for (int half = 0; half < 2; ++half) {
      const int64_t colour = forward ? half : 1 - half;
      for_each_row(s.n, [&](int64_t j, int64_t k) {
        const int64_t row = s.stride[1] * j + s.stride[2] * k;
        const bool inside = poisson_row_inside(s, j, k);
        for (int64_t i = (colour + j + k) % 2; i < s.n[0]; i += 2)
          poisson_relax_at(s, inside, i, j, k, 1.0, inv_diag[row + i], b, x);
      });
    }
    return;
  }
  const double omega = s.dim == 3 ? 6.0 / 7.0 : 4.0 / 5.0;
  double* y = lv.tmp.data();
  for_each_row(s.n, [&](int64_t j, int64_t k) {
    const int64_t row = s.stride[1] * j + s.stride[2] * k;
    const bool inside = poisson_row_inside(s, j, k);
    for (int64_t i = 0; i < s.n[0]; ++i)
      y[row + i] = x[row + i] + omega * inv_diag[row + i] * (b[row + i] - poisson_apply_fast(s, inside, i, j, k, x));
  });
  lv.x.swap(lv.tmp);
}

void MultigridPreconditioner::coarsest_solve(Level& lv) const {
  if (direct_) {
    // Pinned: row 0 of the factored matrix is the identity's, so its right-hand side is 0.
    lv.r = lv.b;
    if (singular_) lv.r[0] = 0;
    (void)coarse_factor_.solve(lv.r, lv.x);
    return;
  }
  lv.x.setZero();
  for (int s = 0; s < opt_.coarse_sweeps; ++s) smooth(lv, true);
  for (int s = 0; s < opt_.coarse_sweeps; ++s) smooth(lv, false);
}

// The V-cycle on level l for A x = b from x = 0: smooth, restrict the residual, correct from the
// coarser level, smooth in the reverse order.
void MultigridPreconditioner::cycle(int l) const {
  Level& lv = levels_[static_cast<size_t>(l)];
  if (l + 1 == levels()) {
    coarsest_solve(lv);
    return;
  }
  Level& cv = levels_[static_cast<size_t>(l) + 1];
  const PoissonStencil& s = lv.s;
  lv.x.setZero();
  for (int k = 0; k < opt_.sweeps; ++k) smooth(lv, true);

  // r = b - A x, then b_coarse = R r with R = P^T / 2^dim: for the constant prolongation the
  // mean of the 2^dim children, for the linear one the full-weighting stencil (1 3 3 1) / 8 per
  // axis.
  const double* x = lv.x.data();
  const double* b = lv.b.data();
  double* r = lv.r.data();
  for_each_row(s.n, [&](int64_t j, int64_t k) {
    const int64_t row = s.stride[1] * j + s.stride[2] * k;
    const bool inside = poisson_row_inside(s, j, k);
    for (int64_t i = 0; i < s.n[0]; ++i) r[row + i] = b[row + i] - poisson_apply_fast(s, inside, i, j, k, x);
  });
  const double scale = 1.0 / static_cast<double>(1 << s.dim);
  double* bc = cv.b.data();
  for_each_row(cv.s.n, [&](int64_t j, int64_t k) {
    const int64_t row = cv.s.stride[1] * j + cv.s.stride[2] * k;
    const Taps& ty = lv.down[1][static_cast<size_t>(j)];
    const Taps& tz = lv.down[2][static_cast<size_t>(k)];
    for (int64_t i = 0; i < cv.s.n[0]; ++i)
      bc[row + i] = scale * tensor_sum(lv.down[0][static_cast<size_t>(i)], ty, tz, s.n, r);
  });

  cycle(l + 1);

  // x += P x_coarse.
  const double* xc = cv.x.data();
  double* xf = lv.x.data();
  for_each_row(s.n, [&](int64_t j, int64_t k) {
    const int64_t row = s.stride[1] * j + s.stride[2] * k;
    const Taps& ty = lv.up[1][static_cast<size_t>(j)];
    const Taps& tz = lv.up[2][static_cast<size_t>(k)];
    for (int64_t i = 0; i < s.n[0]; ++i)
      xf[row + i] += tensor_sum(lv.up[0][static_cast<size_t>(i)], ty, tz, cv.s.n, xc);
  });
  for (int k = 0; k < opt_.sweeps; ++k) smooth(lv, false);
}

void MultigridPreconditioner::apply(const Vector& r, Vector& z) const {
  Level& top = levels_.front();
  top.b = r;
  remove_mean(top.b);
  cycle(0);
  z = top.x;
  remove_mean(z);
}

PoissonSolver::PoissonSolver(const Grid& g, double sigma, const PoissonSolverOptions& opt)
    : opt_(opt), op_(g, sigma), mg_(g, sigma, opt.multigrid), rhs_(Vector::Zero(g.cells())) {}

linalg::SolveReport PoissonSolver::solve(const Eigen::Ref<const Vector>& b, Vector& x) {
  if (x.size() != op_.size()) x = Vector::Zero(op_.size());
  rhs_ = b;
  mg_.remove_mean(rhs_);
  mg_.remove_mean(x);
  linalg::SolveReport rep = linalg::conjugate_gradient(op_, rhs_, x, opt_.cg, &mg_, &cg_);
  mg_.remove_mean(x);
  return rep;
}

}  // namespace silt::fluid
