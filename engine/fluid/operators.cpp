#include "fluid/operators.hpp"

#include <algorithm>
#include <cmath>

#include "core/parallel.hpp"
#include "fluid/stencil_kernels.hpp"

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
  parallel_for(nj * nk, 8, [&](int64_t b, int64_t e) {
    for (int64_t row = b; row < e; ++row) {
      const int64_t j = r[1][0] + row % nj, k = r[2][0] + row / nj;
      f(L.at(r[0][0], j, k), ni, row);
    }
  });
}

template <int D>
void momentum_substep_d(const Grid& g, const Layout& L, const PaddedConst& u, const Padded& u_star,
                        const Padded& n_prev, const PaddedConst& bc_lap, const SubstepCoefficients& k) {
  const double inv_h[3] = {1 / g.h[0], 1 / g.h[1], 1 / g.h[2]};
  const double inv_h2[3] = {inv_h[0] * inv_h[0], inv_h[1] * inv_h[1], inv_h[2] * inv_h[2]};
  const int64_t* s = L.s.data();
  const double* const* c = u.data();
  auto one = [&]<int A>() {
    double* us = u_star[A];
    double* np = n_prev[A];
    const double* ua = u[A];
    const double* lb = bc_lap[A];
    const double f = k.force[A], nu = k.nu, gdt = k.gdt, zdt = k.zdt, beta = k.beta;
    const double* pr = k.p;
    const double gp = k.adt * inv_h[A];
    const int64_t sa = s[A];
    sweep_rows(L, range_of(g, A), [&](int64_t q0, int64_t n, int64_t) {
      if (beta > 0)
        for (int64_t q = q0; q < q0 + n; ++q) {
          const double adv = advection_kernel<D, A>(c, q, s, inv_h) + f;
          const double lap = laplacian_kernel<D>(ua, q, s, inv_h2);
          us[q] = ua[q] + gdt * adv + zdt * np[q] - gp * (pr[q] - pr[q - sa]) + beta * (lap + lb[q]);
          np[q] = adv;
        }
      else
        for (int64_t q = q0; q < q0 + n; ++q) {
          const double rhs = advection_kernel<D, A>(c, q, s, inv_h) + nu * laplacian_kernel<D>(ua, q, s, inv_h2) + f;
          us[q] = ua[q] + gdt * rhs + zdt * np[q] - gp * (pr[q] - pr[q - sa]);
          np[q] = rhs;
        }
    });
  };
  one.template operator()<0>();
  one.template operator()<1>();
  if constexpr (D == 3) one.template operator()<2>();
}

template <int D>
double divergence_d(const Grid& g, const Layout& L, const PaddedConst& u, double* cells, double scale) {
  const double inv_h[3] = {1 / g.h[0], 1 / g.h[1], 1 / g.h[2]};
  const int64_t nj = g.n[1], nk = D == 3 ? g.n[2] : 1, ni = g.n[0];
  const auto mx = parallel_max<1>(nj * nk, 8, [&](int64_t b, int64_t e) {
    double m = 0;
    for (int64_t row = b; row < e; ++row) {
      const int64_t j = row % nj, k = row / nj, q0 = L.at(0, j, k);
      double* o = cells + row * ni;
      for (int64_t i = 0; i < ni; ++i) {
        const double d = divergence_kernel<D>(u.data(), q0 + i, L.s.data(), inv_h);
        o[i] = scale * d;
        m = std::max(m, std::abs(d));
        if (!(std::abs(d) < 1e300)) m = HUGE_VAL;  // NaN: reported as infinite
      }
    }
    return std::array<double, 1>{m};
  });
  return mx[0];
}

}  // namespace

std::array<int64_t, 3> unknown_dims(const Grid& g, int a) {
  const Range3 r = range_of(g, a);
  return {r[0][1] - r[0][0], r[1][1] - r[1][0], r[2][1] - r[2][0]};
}

void momentum_substep(const Grid& g, const Layout& L, const PaddedConst& u, const Padded& u_star, const Padded& n_prev,
                      const PaddedConst& bc_lap, const SubstepCoefficients& c) {
  if (g.dim == 2) momentum_substep_d<2>(g, L, u, u_star, n_prev, bc_lap, c);
  else momentum_substep_d<3>(g, L, u, u_star, n_prev, bc_lap, c);
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

double divergence(const Grid& g, const Layout& L, const PaddedConst& u, double* cells, double scale) {
  return g.dim == 2 ? divergence_d<2>(g, L, u, cells, scale) : divergence_d<3>(g, L, u, cells, scale);
}

void subtract_gradient(const Grid& g, const Layout& L, const Padded& u, const double* phi, double coeff) {
  const double inv_h[3] = {1 / g.h[0], 1 / g.h[1], 1 / g.h[2]};
  const int64_t* s = L.s.data();
  for (int a = 0; a < g.dim; ++a) {
    double* ua = u[a];
    const int64_t sa = s[a];
    const double c = coeff * inv_h[a];
    sweep_rows(L, range_of(g, a), [&](int64_t q0, int64_t n, int64_t) {
      for (int64_t q = q0; q < q0 + n; ++q) ua[q] -= c * (phi[q] - phi[q - sa]);
    });
  }
}

void gather_unknowns(const Grid& g, const Layout& L, int a, const double* padded, double* out) {
  sweep_rows(L, range_of(g, a),
             [&](int64_t q0, int64_t n, int64_t row) { std::copy(padded + q0, padded + q0 + n, out + row * n); });
}

void scatter_unknowns(const Grid& g, const Layout& L, int a, const double* in, double* padded) {
  sweep_rows(L, range_of(g, a),
             [&](int64_t q0, int64_t n, int64_t row) { std::copy(in + row * n, in + row * n + n, padded + q0); });
}

}  // namespace silt::fluid
