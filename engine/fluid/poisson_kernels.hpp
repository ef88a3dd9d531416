// Pointwise kernels of the cell-centred pressure operator
//
//   (A p)_c = sigma p_c - (Lap_h p)_c,
//   (Lap_h p)_c = sum over axes a of (p_{c+e_a} - 2 p_c + p_{c-e_a}) / h_a^2,
//
// the 5-point (2D) or 7-point (3D) Laplacian on the grid of cell centres, with its own spacing
// h_a per axis. sigma = 0 is the projection's Poisson equation; sigma > 0 the shifted (Helmholtz)
// operator of an implicit diffusion step, sigma = 1 / (nu dt).
//
// Beyond a face of the box the stencil reads a ghost value, which makes the boundary condition:
//   - periodic: the cell on the opposite side of the box (c + (n_a - 1) e_a on the low face);
//   - Neumann, dp/dn = 0 on the face: ghost = p_c, the face's difference vanishes and the
//     diagonal loses that face's 1 / h_a^2;
//   - Dirichlet, p = 0 on the face half a cell away: the ghost is the linear extrapolation
//     through the face, ghost = -p_c, and the diagonal gains 1 / h_a^2 (3 / h_a^2 from that axis).
// Each face difference (p_c - p_nb) / h_a^2 appears, with the opposite sign, in the rows of both
// cells it joins, so A is symmetric; it is positive definite unless no face is Dirichlet and
// sigma = 0, where A 1 = 0: the constants are its null space and its range the zero-mean vectors.
//
// A kernel reads a flat array of cells (x fastest: c = i + n0 (j + n1 k)) and is testable on any
// small patch; the loops over the grid are in poisson_operator.cpp and multigrid.cpp.
#pragma once

#include <array>
#include <cstdint>

#include "fluid/grid.hpp"

namespace silt::fluid {

// The constants of the stencil, from the grid and sigma.
struct PoissonStencil {
  int dim = 2;
  std::array<int64_t, 3> n{1, 1, 1};       // cells per axis
  std::array<int64_t, 3> stride{1, 1, 1};  // flat offset of one cell along each axis
  std::array<double, 3> w{0, 0, 0};        // 1 / h_a^2 [1/m^2]; 0 on the axes beyond dim
  std::array<std::array<PressureBc, 2>, 3> bc{};
  double sigma = 0;  // the shift [1/m^2]

  int64_t cells() const { return n[0] * n[1] * n[2]; }
};

inline PoissonStencil make_poisson_stencil(const Grid& g, double sigma) {
  PoissonStencil s;
  s.dim = g.dim;
  s.n = g.n;
  s.stride = {1, g.n[0], g.n[0] * g.n[1]};
  for (int a = 0; a < 3; ++a) {
    s.w[a] = a < g.dim ? 1 / (g.h[a] * g.h[a]) : 0.0;
    for (int side = 0; side < 2; ++side) s.bc[a][side] = a < g.dim ? g.pbc(a, side) : PressureBc::kPeriodic;
  }
  s.sigma = sigma;
  return s;
}

// What lies beyond one face of a cell along axis a (side 0: low, 1: high), for the cell at
// position `idx` along that axis: another cell, at flat offset `offset` (0 when a periodic axis
// has one cell: the cell is its own neighbour), or a ghost worth `ghost_sign` p_c.
struct Across {
  bool ghost = false;
  int64_t offset = 0;
  double ghost_sign = 0;  // +1 Neumann, -1 Dirichlet
};

inline Across across(const PoissonStencil& s, int a, int side, int64_t idx) {
  const int64_t st = s.stride[a];
  if (side == 0 && idx > 0) return {false, -st, 0};
  if (side == 1 && idx < s.n[a] - 1) return {false, st, 0};
  switch (s.bc[a][side]) {
    case PressureBc::kPeriodic: return {false, (side == 0 ? 1 : -1) * (s.n[a] - 1) * st, 0};
    case PressureBc::kNeumann: return {true, 0, 1.0};
    case PressureBc::kDirichlet: return {true, 0, -1.0};
  }
  return {};
}

// (A p) at cell (i, j, k): sigma p_c + sum over the 2 dim faces of (p_c - p_beyond) / h_a^2.
inline double poisson_apply_at(const PoissonStencil& s, int64_t i, int64_t j, int64_t k, const double* p) {
  const std::array<int64_t, 3> idx{i, j, k};
  const int64_t c = i + s.stride[1] * j + s.stride[2] * k;
  const double pc = p[c];
  double v = s.sigma * pc;
  for (int a = 0; a < s.dim; ++a) {
    double sum = 0;
    for (int side = 0; side < 2; ++side) {
      const Across x = across(s, a, side, idx[a]);
      sum += pc - (x.ghost ? x.ghost_sign * pc : p[c + x.offset]);
    }
    v += s.w[a] * sum;
  }
  return v;
}

// Whether row (j, k) of cells along x is away from the faces of the other axes.
inline bool poisson_row_inside(const PoissonStencil& s, int64_t j, int64_t k) {
  return j > 0 && j + 1 < s.n[1] && (s.dim < 3 || (k > 0 && k + 1 < s.n[2]));
}

// (A p) at (i, j, k), without the boundary branches where no face of the cell is on the box
// (`row_inside` from poisson_row_inside): the same operations in the same order as
// poisson_apply_at, so the same bits, at a fraction of the cost in the bulk of the grid.
inline double poisson_apply_fast(const PoissonStencil& s, bool row_inside, int64_t i, int64_t j, int64_t k,
                                 const double* p) {
  if (!row_inside || i == 0 || i + 1 == s.n[0]) return poisson_apply_at(s, i, j, k, p);
  const int64_t c = i + s.stride[1] * j + s.stride[2] * k;
  const double pc = p[c];
  double v = s.sigma * pc;
  v += s.w[0] * ((pc - p[c - 1]) + (pc - p[c + 1]));
  v += s.w[1] * ((pc - p[c - s.stride[1]]) + (pc - p[c + s.stride[1]]));
  if (s.dim == 3) v += s.w[2] * ((pc - p[c - s.stride[2]]) + (pc - p[c + s.stride[2]]));
  return v;
}

// A_cc: sigma + sum over the faces of (1 - the share of p_c in the value beyond) / h_a^2.
inline double poisson_diagonal_at(const PoissonStencil& s, int64_t i, int64_t j, int64_t k) {
  const std::array<int64_t, 3> idx{i, j, k};
  double d = s.sigma;
  for (int a = 0; a < s.dim; ++a)
    for (int side = 0; side < 2; ++side) {
      const Across x = across(s, a, side, idx[a]);
      d += s.w[a] * (1 - (x.ghost ? x.ghost_sign : (x.offset == 0 ? 1.0 : 0.0)));
    }
  return d;
}

// One point of a relaxation sweep: x_c += omega (b_c - (A x)_c) / A_cc. With omega = 1 and no
// neighbour of c updated at the same time, this is the Gauss-Seidel update of cell c.
inline void poisson_relax_at(const PoissonStencil& s, bool row_inside, int64_t i, int64_t j, int64_t k, double omega,
                             double inv_diag, const double* b, double* x) {
  const int64_t c = i + s.stride[1] * j + s.stride[2] * k;
  x[c] += omega * inv_diag * (b[c] - poisson_apply_fast(s, row_inside, i, j, k, x));
}

}  // namespace silt::fluid
