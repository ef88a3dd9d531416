#include "fluid/operators.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/assert.hpp"
#include "core/parallel.hpp"
#include "core/simd_level.hpp"
#include "fluid/stencil_kernels.hpp"
#include "fluid/sweep_for.hpp"

namespace silt::fluid {
namespace {

using Range3 = std::array<std::array<int64_t, 2>, 3>;

Range3 range_of(const Grid& g, int a) {
  Range3 r{{{0, 1}, {0, 1}, {0, 1}}};
  for (int b = 0; b < g.dim; ++b) r[b] = a < 0 ? std::array<int64_t, 2>{0, g.n[b]} : update_range(g, a, b);
  return r;
}

// f(q, count, row) for each row of the range: q the padded index of its first point, row the
// row's rank (x fastest unpadded numbering is row * count + i).
template <class F>
void sweep_rows(const Layout& L, const Range3& r, F&& f) {
  const int64_t nj = r[1][1] - r[1][0], nk = r[2][1] - r[2][0], ni = r[0][1] - r[0][0];
  sweep_for(L.cells(), nj * nk, 8, [&](int64_t b, int64_t e) {
    for (int64_t row = b; row < e; ++row) {
      const int64_t j = r[1][0] + row % nj, k = r[2][0] + row / nj;
      f(L.at(r[0][0], j, k), ni, row);
    }
  });
}

// Calls f.template operator()<M>(q, n) with the mask M of a row's items known at compile time.
template <int K, int M = 1, class F>
void with_mask(int mask, F& f, int64_t q, int64_t n) {
  if constexpr (M < (1 << K)) {
    if (mask == M) f.template operator()<M>(q, n);
    else with_mask<K, M + 1>(mask, f, q, n);
  }
}

// Sweeps K items (the velocity components, the cells), each over its own range, in one pass:
// f.template operator()<M>(q, n) updates the items of mask M at the n points of a row from padded
// index q. In each row of the union of the ranges, the points all of its items share go in one
// call and the rest of each item's points alone, so every point of every range is visited once
// and the grid is read once rather than once per item. Which thread takes a row, and how a row
// is cut, do not depend on the number of threads.
template <int K, class F>
void sweep_fused(const Layout& L, const std::array<Range3, K>& r, F&& f) {
  std::array<int64_t, 2> rj = r[0][1], rk = r[0][2];
  for (int a = 1; a < K; ++a) {
    rj = {std::min(rj[0], r[a][1][0]), std::max(rj[1], r[a][1][1])};
    rk = {std::min(rk[0], r[a][2][0]), std::max(rk[1], r[a][2][1])};
  }
  const int64_t nj = rj[1] - rj[0], nk = rk[1] - rk[0];
  sweep_for(L.cells(), nj * nk, 8, [&](int64_t b, int64_t e) {
    for (int64_t row = b; row < e; ++row) {
      const int64_t j = rj[0] + row % nj, k = rk[0] + row / nj;
      int mask = 0;
      int64_t lo = INT64_MIN, hi = INT64_MAX;  // the points the row's items share
      for (int a = 0; a < K; ++a)
        if (j >= r[a][1][0] && j < r[a][1][1] && k >= r[a][2][0] && k < r[a][2][1]) {
          mask |= 1 << a;
          lo = std::max(lo, r[a][0][0]);
          hi = std::min(hi, r[a][0][1]);
        }
      if (mask == 0) continue;
      const bool shared = hi > lo;
      if (shared) with_mask<K>(mask, f, L.at(lo, j, k), hi - lo);
      for (int a = 0; a < K; ++a) {
        if (!(mask & (1 << a))) continue;
        const int64_t a0 = r[a][0][0], a1 = r[a][0][1];
        if (!shared) {
          if (a1 > a0) with_mask<K>(1 << a, f, L.at(a0, j, k), a1 - a0);
          continue;
        }
        if (a0 < lo) with_mask<K>(1 << a, f, L.at(a0, j, k), lo - a0);
        if (hi < a1) with_mask<K>(1 << a, f, L.at(hi, j, k), a1 - hi);
      }
    }
  });
}

template <int D>
std::array<Range3, D> component_ranges(const Grid& g) {
  std::array<Range3, D> r;
  for (int a = 0; a < D; ++a) r[a] = range_of(g, a);
  return r;
}

// The momentum update of component A at face q (operators.hpp): with the explicit viscous term,
// Crank-Nicolson's explicit half, or backward Euler's boundary values alone.
template <int D, int A, Viscous V>
struct MomentumPoint {
  const double* const* c;
  UnitXStrides s;
  const double *inv_h, *inv_h2;
  const SubstepCoefficients& k;
  double* us;
  double* np;
  const double* lb;
  double gp;
  void operator()(int64_t q) const {
    const double* ua = c[A];
    const double* pr = k.p;
    if constexpr (V == Viscous::kCrankNicolson) {
      const double adv = advection_kernel<D, A>(c, q, s, inv_h) + k.force[A];
      const double lap = laplacian_kernel<D>(ua, q, s, inv_h2);
      us[q] = ua[q] + k.gdt * adv + k.zdt * np[q] - gp * (pr[q] - pr[q - s[A]]) + k.beta * (lap + lb[q]);
      np[q] = adv;
    } else if constexpr (V == Viscous::kBackwardEuler) {
      const double adv = advection_kernel<D, A>(c, q, s, inv_h) + k.force[A];
      us[q] = ua[q] + k.gdt * adv + k.zdt * np[q] - gp * (pr[q] - pr[q - s[A]]) + k.beta * lb[q];
      np[q] = adv;
    } else {
      const double rhs =
          advection_kernel<D, A>(c, q, s, inv_h) + k.nu * laplacian_kernel<D>(ua, q, s, inv_h2) + k.force[A];
      us[q] = ua[q] + k.gdt * rhs + k.zdt * np[q] - gp * (pr[q] - pr[q - s[A]]);
      np[q] = rhs;
    }
  }
};

template <int D, Viscous V>
void momentum_substep_d(const Grid& g, const Layout& L, const PaddedConst& u, const Padded& u_star,
                        const Padded& n_prev, const PaddedConst& bc_lap, const SubstepCoefficients& k) {
  const double inv_h[3] = {1 / g.h[0], 1 / g.h[1], 1 / g.h[2]};
  const double inv_h2[3] = {inv_h[0] * inv_h[0], inv_h[1] * inv_h[1], inv_h[2] * inv_h[2]};
  SILT_ASSERT(L.s[0] == 1, "the padded rows are contiguous along x");
  const UnitXStrides s{L.s[1], L.s[2]};
  auto point = [&]<int A>() {
    return MomentumPoint<D, A, V>{u.data(), s, inv_h, inv_h2, k, u_star[A], n_prev[A], bc_lap[A], k.adt * inv_h[A]};
  };
  const auto p0 = point.template operator()<0>();
  const auto p1 = point.template operator()<1>();
  const auto p2 = point.template operator()<D - 1>();
  // Each component's loop over a row apart: one loop for the three reads more addresses than
  // there are registers, and the row's neighbours stay in the first-level cache between them.
  sweep_fused<D>(L, component_ranges<D>(g), [&]<int M>(int64_t q0, int64_t n) {
    run_simd([&] {
      auto row = [&](const auto& at_face) {
        SILT_IVDEP
        for (int64_t q = q0; q < q0 + n; ++q) at_face(q);
      };
      if constexpr ((M & 1) != 0) row(p0);
      if constexpr ((M & 2) != 0) row(p1);
      if constexpr ((M & 4) != 0) row(p2);
    });
  });
}

// cells = scale * div u row by row; with Max, the largest |div u| of the rows too.
template <int D, bool Max>
double divergence_d(const Grid& g, const Layout& L, const PaddedConst& u, double* cells, double scale) {
  const double inv_h[3] = {1 / g.h[0], 1 / g.h[1], 1 / g.h[2]};
  const int64_t nj = g.n[1], nk = D == 3 ? g.n[2] : 1, ni = g.n[0];
  const auto mx = parallel_max<1>(nj * nk, 8, [&](int64_t b, int64_t e) {
    double m = 0;
    for (int64_t row = b; row < e; ++row) {
      const int64_t j = row % nj, k = row / nj, q0 = L.at(0, j, k);
      double* o = cells + row * ni;
      run_simd([&] {
        SILT_IVDEP
        for (int64_t i = 0; i < ni; ++i) o[i] = scale * divergence_kernel<D>(u.data(), q0 + i, L.s.data(), inv_h);
      });
      if constexpr (Max)
        for (int64_t i = 0; i < ni; ++i) {
          const double a = std::abs(o[i]);
          m = std::max(m, a);
          if (!(a < 1e300)) m = HUGE_VAL;  // NaN: reported as infinite
        }
    }
    return std::array<double, 1>{m};
  });
  return mx[0];
}

// u_a -= coeff grad_a phi on each component's faces and p += phi in the cells, in one sweep.
template <int D>
void project_velocity_d(const Grid& g, const Layout& L, const Padded& u, const double* phi, double coeff, double* p) {
  std::array<Range3, D + 1> r;
  std::array<double, 3> c{};
  for (int a = 0; a < D; ++a) {
    r[a] = range_of(g, a);
    c[a] = coeff * (1 / g.h[a]);  // as the momentum update takes 1 / h
  }
  r[D] = range_of(g, -1);
  constexpr int kCells = 1 << D;  // the item of the cells
  const int64_t* s = L.s.data();
  double* u0 = u[0];
  double* u1 = u[1];
  double* u2 = u[D - 1];
  sweep_fused<D + 1>(L, r, [&]<int M>(int64_t q0, int64_t n) {
    run_simd([&] {
      SILT_IVDEP
      for (int64_t q = q0; q < q0 + n; ++q) {
        if constexpr ((M & 1) != 0) u0[q] -= c[0] * (phi[q] - phi[q - s[0]]);
        if constexpr ((M & 2) != 0) u1[q] -= c[1] * (phi[q] - phi[q - s[1]]);
        if constexpr (D == 3 && (M & 4) != 0) u2[q] -= c[2] * (phi[q] - phi[q - s[2]]);
        if constexpr ((M & kCells) != 0) p[q] += phi[q];
      }
    });
  });
}

}  // namespace

std::array<int64_t, 3> unknown_dims(const Grid& g, int a) {
  const Range3 r = range_of(g, a);
  return {r[0][1] - r[0][0], r[1][1] - r[1][0], r[2][1] - r[2][0]};
}

void momentum_substep(const Grid& g, const Layout& L, const PaddedConst& u, const Padded& u_star, const Padded& n_prev,
                      const PaddedConst& bc_lap, const SubstepCoefficients& c) {
  auto run = [&]<int D>() {
    if (c.viscous == Viscous::kCrankNicolson)
      momentum_substep_d<D, Viscous::kCrankNicolson>(g, L, u, u_star, n_prev, bc_lap, c);
    else if (c.viscous == Viscous::kBackwardEuler)
      momentum_substep_d<D, Viscous::kBackwardEuler>(g, L, u, u_star, n_prev, bc_lap, c);
    else momentum_substep_d<D, Viscous::kExplicit>(g, L, u, u_star, n_prev, bc_lap, c);
  };
  if (g.dim == 2) run.template operator()<2>();
  else run.template operator()<3>();
}

void component_laplacian(const Grid& g, const Layout& L, int a, const double* u, double* out) {
  const double inv_h2[3] = {1 / (g.h[0] * g.h[0]), 1 / (g.h[1] * g.h[1]), 1 / (g.h[2] * g.h[2])};
  const int64_t* s = L.s.data();
  sweep_rows(L, range_of(g, a), [&](int64_t q0, int64_t n, int64_t) {
    if (g.dim == 2)
      for (int64_t q = q0; q < q0 + n; ++q) out[q] = laplacian_kernel<2>(u, q, s, inv_h2);
    else
      for (int64_t q = q0; q < q0 + n; ++q) out[q] = laplacian_kernel<3>(u, q, s, inv_h2);
  });
}

void divergence(const Grid& g, const Layout& L, const PaddedConst& u, double* cells, double scale) {
  if (g.dim == 2) divergence_d<2, false>(g, L, u, cells, scale);
  else divergence_d<3, false>(g, L, u, cells, scale);
}

double divergence_max(const Grid& g, const Layout& L, const PaddedConst& u, double* cells) {
  return g.dim == 2 ? divergence_d<2, true>(g, L, u, cells, 1.0) : divergence_d<3, true>(g, L, u, cells, 1.0);
}

void project_velocity(const Grid& g, const Layout& L, const Padded& u, const double* phi, double coeff, double* p) {
  if (g.dim == 2) project_velocity_d<2>(g, L, u, phi, coeff, p);
  else project_velocity_d<3>(g, L, u, phi, coeff, p);
}

void gather_unknowns(const Grid& g, const Layout& L, int a, const double* padded, double* out) {
  sweep_rows(L, range_of(g, a),
             [&](int64_t q0, int64_t n, int64_t row) { std::copy(padded + q0, padded + q0 + n, out + row * n); });
}

SolveRows unknown_rows(const Grid& g, const Layout& L, int a, double* padded) {
  const Range3 r = range_of(g, a);
  return {padded + L.at(r[0][0], r[1][0], r[2][0]), L.s[1], L.s[2]};
}

void scatter_unknowns(const Grid& g, const Layout& L, int a, const double* in, double* padded) {
  sweep_rows(L, range_of(g, a),
             [&](int64_t q0, int64_t n, int64_t row) { std::copy(in + row * n, in + row * n + n, padded + q0); });
}

}  // namespace silt::fluid
