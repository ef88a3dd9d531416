// The grain passes of velocity Verlet (integrate.cpp) for disks and spheres, with or without an
// affine flow, four grains per AVX2 instruction. The arrays hold the D components of each grain side by
// side, so the 4 D values of four grains are D registers: the updates are done on those as they
// lie, each grain's mass (or inertia) and frozen flag spread to its lanes, and the values that
// need a grain's components together (its squared displacements, the sum whose finiteness is
// checked, the box test) are taken after a transposition to one register per component. Every
// value goes through the same IEEE operations in the same order as in the scalar loop, so both
// give the same bits (tests compare them); a grain that leaves the box or whose values are not
// finite is handed back to the scalar code.
#pragma once

#include <bit>
#include <cstdint>
#include <limits>

#include "dem/grain_pass.hpp"
#include "silt/vec.hpp"

#if defined(__SSE4_1__)
#include <immintrin.h>
#endif

namespace silt::dem::grain_avx2 {

#if defined(__SSE4_1__)
#define SILT_AVX2_INLINE [[gnu::target("avx2"), gnu::always_inline]] inline

// Four grains' values as they lie, D registers (3D: a[0] = [x0 y0 z0 x1], a[1] = [y1 z1 x2 y2],
// a[2] = [z2 x3 y3 z3]; 2D: a[0] = [x0 y0 x1 y1], a[1] = [x2 y2 x3 y3]), as one register per
// component: c[0] = [x0 x1 x2 x3], c[1] = the y, ...
template <int D>
SILT_AVX2_INLINE void transpose(const __m256d* a, __m256d* c) {
  if constexpr (D == 3) {
    c[0] = _mm256_permute4x64_pd(_mm256_blend_pd(_mm256_blend_pd(a[0], a[1], 0b0100), a[2], 0b0010),
                                 _MM_SHUFFLE(1, 2, 3, 0));
    c[1] = _mm256_permute4x64_pd(_mm256_blend_pd(_mm256_blend_pd(a[0], a[1], 0b1001), a[2], 0b0100),
                                 _MM_SHUFFLE(2, 3, 0, 1));
    c[2] = _mm256_permute4x64_pd(_mm256_blend_pd(_mm256_blend_pd(a[0], a[1], 0b0010), a[2], 0b1001),
                                 _MM_SHUFFLE(3, 0, 1, 2));
  } else {
    c[0] = _mm256_permute4x64_pd(_mm256_unpacklo_pd(a[0], a[1]), _MM_SHUFFLE(3, 1, 2, 0));
    c[1] = _mm256_permute4x64_pd(_mm256_unpackhi_pd(a[0], a[1]), _MM_SHUFFLE(3, 1, 2, 0));
  }
}

// One value per grain, p = [p0 p1 p2 p3], spread to the lanes of the grains' D components.
template <int D>
SILT_AVX2_INLINE void spread(__m256d p, __m256d* e) {
  if constexpr (D == 3) {
    e[0] = _mm256_permute4x64_pd(p, _MM_SHUFFLE(1, 0, 0, 0));
    e[1] = _mm256_permute4x64_pd(p, _MM_SHUFFLE(2, 2, 1, 1));
    e[2] = _mm256_permute4x64_pd(p, _MM_SHUFFLE(3, 3, 3, 2));
  } else if constexpr (D == 2) {
    e[0] = _mm256_permute4x64_pd(p, _MM_SHUFFLE(1, 1, 0, 0));
    e[1] = _mm256_permute4x64_pd(p, _MM_SHUFFLE(3, 3, 2, 2));
  } else {
    e[0] = p;
  }
}

// A vector of D components per grain (gravity) as the lanes of D registers.
template <int D>
SILT_AVX2_INLINE void pattern(const double* g, __m256d* e) {
  for (int k = 0; k < D; ++k)
    e[k] = _mm256_setr_pd(g[(4 * k) % D], g[(4 * k + 1) % D], g[(4 * k + 2) % D], g[(4 * k + 3) % D]);
}

// All bits set in the lanes of D registers (as pattern lays them) that hold an x component.
template <int D>
SILT_AVX2_INLINE void x_lanes(__m256d* e) {
  const double on = std::bit_cast<double>(~uint64_t{0});
  for (int k = 0; k < D; ++k) {
    double l[4];
    for (int j = 0; j < 4; ++j) l[j] = (4 * k + j) % D == 0 ? on : 0.0;
    e[k] = _mm256_loadu_pd(l);
  }
}

// All bits set in the lane of each frozen grain of four.
SILT_AVX2_INLINE __m256d frozen_mask(const uint8_t* frozen) {
  int32_t bytes;
  __builtin_memcpy(&bytes, frozen, sizeof bytes);
  const __m256i wide = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(bytes));
  return _mm256_castsi256_pd(_mm256_cmpgt_epi64(wide, _mm256_setzero_si256()));
}

// Four grains' masses, inertias and frozen flags, spread to the lanes of their components (and
// of their rotation components).
template <int D>
struct GroupLanes {
  static constexpr int R = kRotDim<D>;
  __m256d frz, im[D], ii[R], fz[D], fr[R];
  [[gnu::target("avx2"), gnu::always_inline]] GroupLanes(const double* inv_m, const double* inv_i,
                                                         const uint8_t* frozen, int64_t i) {
    frz = frozen_mask(frozen + i);
    spread<D>(_mm256_loadu_pd(inv_m + i), im);
    spread<R>(_mm256_loadu_pd(inv_i + i), ii);
    spread<D>(frz, fz);
    spread<R>(frz, fr);
  }
};

SILT_AVX2_INLINE __m256d load(const double* p, int k) { return _mm256_loadu_pd(p + 4 * k); }
SILT_AVX2_INLINE void store(double* p, int k, __m256d v) { _mm256_storeu_pd(p + 4 * k, v); }

// w += h t / I on the R rotation components of four grains (frozen ones kept), the values
// stored returned in ws.
template <int R>
SILT_AVX2_INLINE void spin_kick(double* w, const double* t, const __m256d* ii, const __m256d* fz, __m256d h,
                                __m256d* ws) {
  for (int k = 0; k < R; ++k) {
    const __m256d w0 = load(w, k);
    const __m256d wk = _mm256_add_pd(w0, _mm256_mul_pd(_mm256_mul_pd(h, load(t, k)), ii[k]));
    ws[k] = _mm256_blendv_pd(wk, w0, fz[k]);
    store(w, k, ws[k]);
  }
}

// Half kick and drift of grains [b, b + 4 m). The grains of `redo` (bit l of entry k: grain
// b + 4 k + l) left the box or have a position that is not finite: their values are stored as
// the vector computed them, and the scalar code finishes them (raise, wrap). worst[0] and
// worst[1] are raised to the largest squared displacement since the last build and the largest
// squared step of the grains that are not frozen.
template <int D, bool Affine>
[[gnu::target("avx2")]] inline void drift_grains(const grain_pass::DriftArgs<D> a, int64_t b, int64_t m, double* worst,
                                                 uint8_t* redo) {
  constexpr int R = kRotDim<D>;
  const __m256d h = _mm256_set1_pd(a.h), dt = _mm256_set1_pd(a.dt);
  __m256d g[D], lo_e[D], lam[D], xl[D];
  pattern<D>(a.g, g);
  pattern<D>(a.lo, lo_e);
  pattern<D>(a.lambda, lam);
  x_lanes<D>(xl);
  // The affine flow's terms: (h gd) c_y on the x lanes, (dt gd) (y + dt v_y / 2 - lo_y) on x.
  const __m256d hgd = _mm256_set1_pd(a.h * a.gd), dtgd = _mm256_set1_pd(a.dt * a.gd);
  const __m256d half_dt = _mm256_set1_pd(0.5 * a.dt), lo_y = _mm256_set1_pd(a.lo[1]);
  const bool shear_kick = a.gd != 0.0;
  const __m256d sign = _mm256_set1_pd(-0.0), inf = _mm256_set1_pd(__builtin_inf());
  // The box test of each axis, lo <= x < hi as PeriodicImage::wrap takes it (-inf and inf on an
  // axis that is not periodic).
  __m256d lo[D], hi[D];
  for (int k = 0; k < D; ++k) {
    const double l = a.img.periodic[k] ? a.box.lo[k] : -std::numeric_limits<double>::infinity();
    lo[k] = _mm256_set1_pd(l);
    hi[k] = _mm256_set1_pd(a.img.periodic[k] ? a.box.lo[k] + a.img.len[k] : std::numeric_limits<double>::infinity());
  }
  __m256d wd = _mm256_setzero_pd(), ws = _mm256_setzero_pd();
  for (int64_t q = 0; q < m; ++q) {
    const int64_t i = b + 4 * q;
    double* x = a.x + D * i;
    double* v = a.v + D * i;
    double* disp = a.disp + D * i;
    const double* f = a.f + D * i;
    const GroupLanes<D> gl(a.inv_m, a.inv_i, a.frozen, i);
    const __m256d frz = gl.frz;
    const __m256d *im = gl.im, *ii = gl.ii, *fz = gl.fz, *fr = gl.fr;
    __m256d x0[D], v0[D], cy[D];
    for (int k = 0; k < D; ++k) {
      x0[k] = load(x, k);
      v0[k] = load(v, k);
    }
    if constexpr (Affine) {
      __m256d c[D];
      transpose<D>(v0, c);
      spread<D>(c[1], cy);  // each grain's c_y(t) on its lanes
    }
    __m256d xn[D], dn[D], st[D], vn[D];
    for (int k = 0; k < D; ++k) {
      // v + h (f / m + g); step = dt v; the new position and displacement.
      __m256d vk = _mm256_add_pd(v0[k], _mm256_mul_pd(h, _mm256_add_pd(_mm256_mul_pd(load(f, k), im[k]), g[k])));
      if constexpr (Affine)
        if (shear_kick) vk = _mm256_blendv_pd(vk, _mm256_sub_pd(vk, _mm256_mul_pd(hgd, cy[k])), xl[k]);
      st[k] = _mm256_mul_pd(dt, vk);
      if constexpr (Affine) {
        xn[k] = _mm256_add_pd(lo_e[k], _mm256_mul_pd(lam[k], _mm256_add_pd(_mm256_sub_pd(x0[k], lo_e[k]), st[k])));
        vn[k] = _mm256_mul_pd(vk, lam[k]);
      } else {
        xn[k] = _mm256_add_pd(x0[k], st[k]);
        vn[k] = vk;
      }
      const __m256d d0 = load(disp, k);
      dn[k] = _mm256_add_pd(d0, st[k]);
      store(v, k, _mm256_blendv_pd(vn[k], v0[k], fz[k]));
      store(disp, k, _mm256_blendv_pd(dn[k], d0, fz[k]));
    }
    if constexpr (Affine) {
      // The shear flow at the mid-step height, from y(t) and the new c_y.
      __m256d py[D], pv[D], term[D];
      transpose<D>(x0, py);
      transpose<D>(vn, pv);
      spread<D>(_mm256_mul_pd(dtgd, _mm256_sub_pd(_mm256_add_pd(py[1], _mm256_mul_pd(half_dt, pv[1])), lo_y)), term);
      for (int k = 0; k < D; ++k) xn[k] = _mm256_blendv_pd(xn[k], _mm256_add_pd(xn[k], term[k]), xl[k]);
    }
    for (int k = 0; k < D; ++k) store(x, k, _mm256_blendv_pd(xn[k], x0[k], fz[k]));
    __m256d wn[R];
    spin_kick<R>(a.w + R * i, a.t + R * i, ii, fr, h, wn);
    __m256d c[D], s[D], p[D];
    transpose<D>(dn, c);
    transpose<D>(st, s);
    transpose<D>(xn, p);
    __m256d d2 = _mm256_mul_pd(c[0], c[0]), s2 = _mm256_mul_pd(s[0], s[0]), xs = p[0];
    for (int k = 1; k < D; ++k) {
      d2 = _mm256_add_pd(d2, _mm256_mul_pd(c[k], c[k]));
      s2 = _mm256_add_pd(s2, _mm256_mul_pd(s[k], s[k]));
      xs = _mm256_add_pd(xs, p[k]);
    }
    // A NaN stays out of the maxima, as in std::max(worst, d2); frozen grains count as 0.
    wd = _mm256_max_pd(_mm256_andnot_pd(frz, d2), wd);
    ws = _mm256_max_pd(_mm256_andnot_pd(frz, s2), ws);
    __m256d ok = _mm256_cmp_pd(_mm256_andnot_pd(sign, xs), inf, _CMP_LT_OQ);
    for (int k = 0; k < D; ++k) {
      ok = _mm256_and_pd(ok, _mm256_cmp_pd(p[k], lo[k], _CMP_GE_OQ));
      ok = _mm256_and_pd(ok, _mm256_cmp_pd(p[k], hi[k], _CMP_LT_OQ));
    }
    redo[q] = static_cast<uint8_t>(
        _mm256_movemask_pd(_mm256_andnot_pd(_mm256_or_pd(ok, frz), _mm256_castsi256_pd(_mm256_set1_epi64x(-1)))));
  }
  double l[8];
  _mm256_storeu_pd(l, wd);
  _mm256_storeu_pd(l + 4, ws);
  for (int k = 0; k < 4; ++k) {
    worst[0] = l[k] > worst[0] ? l[k] : worst[0];
    worst[1] = l[4 + k] > worst[1] ? l[4 + k] : worst[1];
  }
}

// The second half kick of grains [b, b + 4 m), without other force sources; under shear (Shear:
// gd != 0), v_x -= h gd c_y as in the scalar loop. redo[q] has the bits of all four grains of
// group q set unless every velocity stored for them is below 1e300 in magnitude (then the sum of
// each grain's velocities, which the scalar code checks, is finite); the caller checks those.
template <int D, bool Shear>
[[gnu::target("avx2")]] inline void kick_grains(const grain_pass::KickArgs<D> a, int64_t b, int64_t m, uint8_t* redo) {
  constexpr int R = kRotDim<D>;
  const __m256d h = _mm256_set1_pd(a.h), hgd = _mm256_set1_pd(a.h * a.gd);
  __m256d g[D], xl[D];
  pattern<D>(a.g, g);
  x_lanes<D>(xl);
  const __m256d sign = _mm256_set1_pd(-0.0), big = _mm256_set1_pd(1e300);
  for (int64_t q = 0; q < m; ++q) {
    const int64_t i = b + 4 * q;
    double* v = a.v + D * i;
    const double* f = a.force + D * i;
    const GroupLanes<D> gl(a.inv_m, a.inv_i, a.frozen, i);
    const __m256d *im = gl.im, *ii = gl.ii, *fz = gl.fz, *fr = gl.fr;
    __m256d ok = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    __m256d v0[D], vk[D];
    for (int k = 0; k < D; ++k) {
      v0[k] = load(v, k);
      vk[k] = _mm256_add_pd(v0[k], _mm256_mul_pd(h, _mm256_add_pd(_mm256_mul_pd(load(f, k), im[k]), g[k])));
    }
    if constexpr (Shear) {
      // v_x -= h gd c_y(t + dt), with the kicked c_y.
      __m256d c[D], cy[D];
      transpose<D>(vk, c);
      spread<D>(c[1], cy);
      for (int k = 0; k < D; ++k)
        vk[k] = _mm256_blendv_pd(vk[k], _mm256_sub_pd(vk[k], _mm256_mul_pd(hgd, cy[k])), xl[k]);
    }
    for (int k = 0; k < D; ++k) {
      const __m256d vs = _mm256_blendv_pd(vk[k], v0[k], fz[k]);
      store(v, k, vs);
      ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_andnot_pd(sign, vs), big, _CMP_LT_OQ));
    }
    __m256d wn[R];
    spin_kick<R>(a.w + R * i, a.torq + R * i, ii, fr, h, wn);
    for (int k = 0; k < R; ++k) ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_andnot_pd(sign, wn[k]), big, _CMP_LT_OQ));
    redo[q] = _mm256_movemask_pd(ok) != 0xF ? 0xF : 0;  // the group's four grains
  }
}
#undef SILT_AVX2_INLINE
#endif

}  // namespace silt::dem::grain_avx2
