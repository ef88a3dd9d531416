// The grain passes of velocity Verlet (integrate.cpp) for spheres without an affine flow, four
// grains per AVX2 instruction. The arrays hold the three components of each grain side by side,
// so the twelve values of four grains are three registers: the updates are done on those as they
// lie, each grain's mass (or inertia) and frozen flag spread to its three lanes, and the values
// that need a grain's three components together (its squared displacements, the sum whose
// finiteness is checked, the box test) are taken after a transposition to one register per
// component. Every value goes through the same IEEE operations in the same order as in the
// scalar loop, so both give the same bits (tests compare them); a grain that leaves the box or
// whose values are not finite is handed back to the scalar code.
#pragma once

#include <cstdint>
#include <limits>

#include "dem/grain_pass.hpp"

#if defined(__SSE4_1__)
#include <immintrin.h>
#endif

namespace silt::dem::grain_avx2 {

#if defined(__SSE4_1__)
#define SILT_AVX2_INLINE [[gnu::target("avx2"), gnu::always_inline]] inline

// Four grains' values, a0 = [x0 y0 z0 x1], a1 = [y1 z1 x2 y2], a2 = [z2 x3 y3 z3], as
// c[0] = [x0 x1 x2 x3], c[1] = the y, c[2] = the z.
SILT_AVX2_INLINE void transpose(__m256d a0, __m256d a1, __m256d a2, __m256d* c) {
  c[0] = _mm256_permute4x64_pd(_mm256_blend_pd(_mm256_blend_pd(a0, a1, 0b0100), a2, 0b0010), _MM_SHUFFLE(1, 2, 3, 0));
  c[1] = _mm256_permute4x64_pd(_mm256_blend_pd(_mm256_blend_pd(a0, a1, 0b1001), a2, 0b0100), _MM_SHUFFLE(2, 3, 0, 1));
  c[2] = _mm256_permute4x64_pd(_mm256_blend_pd(_mm256_blend_pd(a0, a1, 0b0010), a2, 0b1001), _MM_SHUFFLE(3, 0, 1, 2));
}

// One value per grain, p = [p0 p1 p2 p3], spread to the lanes of the grains' components.
SILT_AVX2_INLINE void spread(__m256d p, __m256d* e) {
  e[0] = _mm256_permute4x64_pd(p, _MM_SHUFFLE(1, 0, 0, 0));
  e[1] = _mm256_permute4x64_pd(p, _MM_SHUFFLE(2, 2, 1, 1));
  e[2] = _mm256_permute4x64_pd(p, _MM_SHUFFLE(3, 3, 3, 2));
}

// All bits set in the lane of each frozen grain of four.
SILT_AVX2_INLINE __m256d frozen_mask(const uint8_t* frozen) {
  int32_t bytes;
  __builtin_memcpy(&bytes, frozen, sizeof bytes);
  const __m256i wide = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(bytes));
  return _mm256_castsi256_pd(_mm256_cmpgt_epi64(wide, _mm256_setzero_si256()));
}

SILT_AVX2_INLINE __m256d load(const double* p, int k) { return _mm256_loadu_pd(p + 4 * k); }
SILT_AVX2_INLINE void store(double* p, int k, __m256d v) { _mm256_storeu_pd(p + 4 * k, v); }

// Half kick and drift of grains [b, b + 4 m). The grains of `redo` (bit l of entry k: grain
// b + 4 k + l) left the box or have a position that is not finite: their values are stored as
// the vector computed them, and the scalar code finishes them (raise, wrap). worst[0] and
// worst[1] are raised to the largest squared displacement since the last build and the largest
// squared step of the grains that are not frozen.
[[gnu::target("avx2")]] inline void drift_spheres(const grain_pass::DriftArgs<3> a, int64_t b, int64_t m, double* worst,
                                                  uint8_t* redo) {
  const __m256d h = _mm256_set1_pd(a.h), dt = _mm256_set1_pd(a.dt);
  const __m256d g[3] = {_mm256_setr_pd(a.g[0], a.g[1], a.g[2], a.g[0]), _mm256_setr_pd(a.g[1], a.g[2], a.g[0], a.g[1]),
                        _mm256_setr_pd(a.g[2], a.g[0], a.g[1], a.g[2])};
  const __m256d sign = _mm256_set1_pd(-0.0), inf = _mm256_set1_pd(__builtin_inf());
  // The box test of each axis, lo <= x < hi as PeriodicImage::wrap takes it (-inf and inf on an
  // axis that is not periodic).
  __m256d lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    const double l = a.img.periodic[k] ? a.box.lo[k] : -std::numeric_limits<double>::infinity();
    lo[k] = _mm256_set1_pd(l);
    hi[k] = _mm256_set1_pd(a.img.periodic[k] ? a.box.lo[k] + a.img.len[k] : std::numeric_limits<double>::infinity());
  }
  __m256d wd = _mm256_setzero_pd(), ws = _mm256_setzero_pd();
  for (int64_t q = 0; q < m; ++q) {
    const int64_t i = b + 4 * q;
    double* x = a.x + 3 * i;
    double* v = a.v + 3 * i;
    double* w = a.w + 3 * i;
    double* disp = a.disp + 3 * i;
    const double* f = a.f + 3 * i;
    const double* t = a.t + 3 * i;
    const __m256d frz = frozen_mask(a.frozen + i);
    __m256d im[3], ii[3], fz[3];
    spread(_mm256_loadu_pd(a.inv_m + i), im);
    spread(_mm256_loadu_pd(a.inv_i + i), ii);
    spread(frz, fz);
    __m256d xn[3], dn[3], st[3];
    for (int k = 0; k < 3; ++k) {
      // v + h (f / m + g); step = dt v; the new position and displacement.
      const __m256d v0 = load(v, k), x0 = load(x, k), d0 = load(disp, k);
      const __m256d vk = _mm256_add_pd(v0, _mm256_mul_pd(h, _mm256_add_pd(_mm256_mul_pd(load(f, k), im[k]), g[k])));
      st[k] = _mm256_mul_pd(dt, vk);
      xn[k] = _mm256_add_pd(x0, st[k]);
      dn[k] = _mm256_add_pd(d0, st[k]);
      store(v, k, _mm256_blendv_pd(vk, v0, fz[k]));
      store(x, k, _mm256_blendv_pd(xn[k], x0, fz[k]));
      store(disp, k, _mm256_blendv_pd(dn[k], d0, fz[k]));
      const __m256d w0 = load(w, k);
      const __m256d wk = _mm256_add_pd(w0, _mm256_mul_pd(_mm256_mul_pd(h, load(t, k)), ii[k]));
      store(w, k, _mm256_blendv_pd(wk, w0, fz[k]));
    }
    __m256d c[3], s[3], p[3];
    transpose(dn[0], dn[1], dn[2], c);
    transpose(st[0], st[1], st[2], s);
    transpose(xn[0], xn[1], xn[2], p);
    __m256d d2 = _mm256_mul_pd(c[0], c[0]), s2 = _mm256_mul_pd(s[0], s[0]);
    for (int k = 1; k < 3; ++k) {
      d2 = _mm256_add_pd(d2, _mm256_mul_pd(c[k], c[k]));
      s2 = _mm256_add_pd(s2, _mm256_mul_pd(s[k], s[k]));
    }
    // A NaN stays out of the maxima, as in std::max(worst, d2); frozen grains count as 0.
    wd = _mm256_max_pd(_mm256_andnot_pd(frz, d2), wd);
    ws = _mm256_max_pd(_mm256_andnot_pd(frz, s2), ws);
    const __m256d xs = _mm256_add_pd(_mm256_add_pd(p[0], p[1]), p[2]);
    __m256d ok = _mm256_cmp_pd(_mm256_andnot_pd(sign, xs), inf, _CMP_LT_OQ);
    for (int k = 0; k < 3; ++k) {
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

// The second half kick of grains [b, b + 4 m), without shear and without other force sources.
// redo[k] is set unless every velocity of the four grains b + 4 k .. is below 1e300 in
// magnitude (then the sums of each grain's velocities, which the scalar code checks, are finite);
// the caller checks the grains of those entries.
[[gnu::target("avx2")]] inline void kick_spheres(const grain_pass::KickArgs<3> a, int64_t b, int64_t m, uint8_t* redo) {
  const __m256d h = _mm256_set1_pd(a.h);
  const __m256d g[3] = {_mm256_setr_pd(a.g[0], a.g[1], a.g[2], a.g[0]), _mm256_setr_pd(a.g[1], a.g[2], a.g[0], a.g[1]),
                        _mm256_setr_pd(a.g[2], a.g[0], a.g[1], a.g[2])};
  const __m256d sign = _mm256_set1_pd(-0.0), big = _mm256_set1_pd(1e300);
  for (int64_t q = 0; q < m; ++q) {
    const int64_t i = b + 4 * q;
    double* v = a.v + 3 * i;
    double* w = a.w + 3 * i;
    const double* f = a.force + 3 * i;
    const double* t = a.torq + 3 * i;
    __m256d im[3], ii[3], fz[3];
    spread(_mm256_loadu_pd(a.inv_m + i), im);
    spread(_mm256_loadu_pd(a.inv_i + i), ii);
    spread(frozen_mask(a.frozen + i), fz);
    __m256d ok = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    for (int k = 0; k < 3; ++k) {
      const __m256d v0 = load(v, k), w0 = load(w, k);
      const __m256d vk = _mm256_add_pd(v0, _mm256_mul_pd(h, _mm256_add_pd(_mm256_mul_pd(load(f, k), im[k]), g[k])));
      const __m256d wk = _mm256_add_pd(w0, _mm256_mul_pd(_mm256_mul_pd(h, load(t, k)), ii[k]));
      const __m256d vs = _mm256_blendv_pd(vk, v0, fz[k]), wsel = _mm256_blendv_pd(wk, w0, fz[k]);
      store(v, k, vs);
      store(w, k, wsel);
      ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_andnot_pd(sign, vs), big, _CMP_LT_OQ));
      ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_andnot_pd(sign, wsel), big, _CMP_LT_OQ));
    }
    redo[q] = static_cast<uint8_t>(_mm256_movemask_pd(ok) != 0xF);
  }
}
#undef SILT_AVX2_INLINE
#endif

}  // namespace silt::dem::grain_avx2
