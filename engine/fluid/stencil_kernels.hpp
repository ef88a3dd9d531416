// Pointwise kernels of the staggered grid (Harlow & Welch 1965; Izard 2014 sec. 2.2.1): each
// computes one value at padded index q from its neighbours at the strides s of a Layout; the
// drivers (fluid/operators.cpp) sweep them over the grid and fill the ghosts first.
//
// Component a of the velocity lives on the faces normal to axis a: c[a][q] at face (i, j, k) is
// at x_a = lo_a + i_a h_a and at the cell centres along the other axes. The pressure is at the
// cell centres. Cell (i, j, k) lies between faces i and i + 1 of each axis.
#pragma once

#include <cstdint>

namespace silt::fluid {

// The strides of a padded layout (fluid/layout.hpp) with the x stride known to be 1 when compiled,
// so that a kernel reaches the x neighbours of a point at constant offsets from one address
// instead of holding one more address for each: a kernel of many neighbours then fits in the
// registers. The kernels take these or the layout's stride array.
struct UnitXStrides {
  int64_t y = 0, z = 0;
  constexpr int64_t operator[](int b) const { return b == 0 ? 1 : (b == 1 ? y : z); }
};

// Advection -div(u_a u) of component a at face q, in divergence form with centred averages
// (Morinishi et al. 1998, "Div.-S2"): with a discretely divergence-free velocity it conserves
// both momentum and kinetic energy, so that the inviscid scheme neither creates nor destroys
// energy apart from the time integration's error. Along axis a, the flux (u_a)^2 at the cell
// centres between faces; along b != a, the flux u_b u_a at the edges, both averaged from the two
// neighbouring values:
//   N_a = - sum_b [ F_b(q + 1/2 e_b) - F_b(q - 1/2 e_b) ] / h_b.
template <int D, int A, class S>
inline double advection_kernel(const double* const* c, int64_t q, const S& s, const double* inv_h) {
  const double* ca = c[A];
  double n = 0;
  for (int b = 0; b < D; ++b) {
    double fp, fm;
    if (b == A) {
      const double up = ca[q] + ca[q + s[A]], um = ca[q - s[A]] + ca[q];
      fp = 0.25 * up * up;
      fm = 0.25 * um * um;
    } else {
      const double* cb = c[b];
      fp = 0.25 * (cb[q + s[b] - s[A]] + cb[q + s[b]]) * (ca[q] + ca[q + s[b]]);
      fm = 0.25 * (cb[q - s[A]] + cb[q]) * (ca[q - s[b]] + ca[q]);
    }
    n -= (fp - fm) * inv_h[b];
  }
  return n;
}

// Laplacian of one component (or of the pressure) at q: sum_b (f(q + e_b) - 2 f(q) + f(q - e_b)) / h_b^2.
template <int D, class S>
inline double laplacian_kernel(const double* f, int64_t q, const S& s, const double* inv_h2) {
  double l = 0;
  for (int b = 0; b < D; ++b) l += (f[q + s[b]] - 2 * f[q] + f[q - s[b]]) * inv_h2[b];
  return l;
}

// Divergence of the velocity in cell q: sum_b (u_b(face i_b + 1) - u_b(face i_b)) / h_b.
template <int D>
inline double divergence_kernel(const double* const* c, int64_t q, const int64_t* s, const double* inv_h) {
  double d = 0;
  for (int b = 0; b < D; ++b) d += (c[b][q + s[b]] - c[b][q]) * inv_h[b];
  return d;
}

// Gradient of a cell-centred scalar along a at face q: (p(cell i) - p(cell i - 1)) / h_a.
template <int A>
inline double gradient_kernel(const double* p, int64_t q, const int64_t* s, const double* inv_h) {
  return (p[q] - p[q - s[A]]) * inv_h[A];
}

// Vorticity component about axis c (= the axis other than a and b, a < b cyclic: z for (x, y))
// at the edge shared by faces q of components a and b, i.e. at (i - 1/2, j - 1/2) in the cell
// indices of q: d u_b / d x_a - d u_a / d x_b.
template <int A, int B>
inline double vorticity_kernel(const double* const* c, int64_t q, const int64_t* s, const double* inv_h) {
  return (c[B][q] - c[B][q - s[A]]) * inv_h[A] - (c[A][q] - c[A][q - s[B]]) * inv_h[B];
}

// Vorticity at the centre of the cell at q (w[0] in 2D: the z component; x, y, z in 3D): each
// component the mean of its four edge values around the cell (in 2D, the four corners).
template <int D>
inline void cell_vorticity_kernel(const double* const* c, int64_t q, const int64_t* s, const double* inv_h, double* w) {
  // omega_z at edges (i, j), (i+1, j), (i, j+1), (i+1, j+1), at the cell's z centre.
  const double wz =
      0.25 * (vorticity_kernel<0, 1>(c, q, s, inv_h) + vorticity_kernel<0, 1>(c, q + s[0], s, inv_h) +
              vorticity_kernel<0, 1>(c, q + s[1], s, inv_h) + vorticity_kernel<0, 1>(c, q + s[0] + s[1], s, inv_h));
  if constexpr (D == 2) {
    w[0] = wz;
  } else {
    w[0] =
        0.25 * (vorticity_kernel<1, 2>(c, q, s, inv_h) + vorticity_kernel<1, 2>(c, q + s[1], s, inv_h) +
                vorticity_kernel<1, 2>(c, q + s[2], s, inv_h) + vorticity_kernel<1, 2>(c, q + s[1] + s[2], s, inv_h));
    // omega_y = d u/dz - d w/dx: the (z, x) pair taken in that order.
    w[1] =
        0.25 * (vorticity_kernel<2, 0>(c, q, s, inv_h) + vorticity_kernel<2, 0>(c, q + s[0], s, inv_h) +
                vorticity_kernel<2, 0>(c, q + s[2], s, inv_h) + vorticity_kernel<2, 0>(c, q + s[0] + s[2], s, inv_h));
    w[2] = wz;
  }
}

// to = from * scale over a row of n values (the padded arrays' rows and the State's or the
// unknowns' never overlap; restrict lets GCC vectorise it at every level without overlap checks).
inline void scaled_copy(const double* __restrict from, double* __restrict to, int64_t n, double scale) {
  for (int64_t i = 0; i < n; ++i) to[i] = from[i] * scale;
}

}  // namespace silt::fluid
