// Which listed pairs are within reach: the test of the touch pass (touch_pass.hpp), and of the
// selection of contact candidates (contact_candidates.hpp), which is the same with a margin.
//
// scan_pairs tests entries [q0, q1) (grains pi[q], pj[q]) for |d| < r_i + r_j (+ reach), with
// d = x_i - x_j the nearest-image separation, and hands each entry, in order, to the sink with
// d, the outcome and a count that the sink returns updated (kept here, in a register: sinks
// capture by value, so that their stores cannot alias what the loop keeps). Four entries go
// through the AVX2 registers at once where the processor has them (simd_level.hpp), else two
// through the SSE registers: the same IEEE operations, in the same order, as the scalar loop,
// so all give the same bits. The scalar loop handles the last entries and builds without
// SSE4.1.
#pragma once

#include <cstdint>

#if defined(__SSE4_1__)
#include <immintrin.h>
#endif

#include "core/simd_level.hpp"
#include "core/small_vec.hpp"
#include "silt/periodic_image.hpp"

namespace silt::dem {

namespace scan_detail {

// Entries [q, q1) one at a time.
template <int D, bool Reach, class Sink>
[[gnu::always_inline]] inline int64_t scalar(const double* __restrict x, const double* __restrict r,
                                             const int32_t* __restrict pi, const int32_t* __restrict pj,
                                             const PeriodicImage<D>& img, double reach, int64_t q, int64_t q1,
                                             int64_t c, const Sink& sink) {
  using V = SVec<D>;
  for (; q < q1; ++q) {
    const int64_t i = pi[q], j = pj[q];
    V d = V::load(x + D * i) - V::load(x + D * j);
    img.apply(d);
    double rs = r[i] + r[j];
    if constexpr (Reach) rs += reach;
    double dd[D];
    d.store(dd);
    c = sink(q, dd, static_cast<uint8_t>(d.squaredNorm() < rs * rs), c);
  }
  return c;
}

#if defined(__SSE4_1__)
constexpr int kRound = _MM_FROUND_CUR_DIRECTION | _MM_FROUND_NO_EXC;  // std::nearbyint

// a[e0], a[e1], a[e2], a[e3] in one register.
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d four(const double* a, int64_t e0, int64_t e1, int64_t e2,
                                                                int64_t e3) {
  return _mm256_set_m128d(_mm_loadh_pd(_mm_load_sd(a + e2), a + e3), _mm_loadh_pd(_mm_load_sd(a + e0), a + e1));
}

// The separations d (one register per component) of entries q .. q + 3 and which of them are
// within reach (bit e for entry q + e).
template <int D, bool Reach>
[[gnu::target("avx2"), gnu::always_inline]] inline int four_separations(
    const double* __restrict x, const double* __restrict r, const int32_t* __restrict pi, const int32_t* __restrict pj,
    const PeriodicImage<D>& img, double reach, int64_t q, __m256d* d, __m256d* d2_out = nullptr) {
  const int64_t i0 = pi[q], i1 = pi[q + 1], i2 = pi[q + 2], i3 = pi[q + 3];
  const int64_t j0 = pj[q], j1 = pj[q + 1], j2 = pj[q + 2], j3 = pj[q + 3];
  for (int k = 0; k < D; ++k)
    d[k] = _mm256_sub_pd(four(x + k, D * i0, D * i1, D * i2, D * i3), four(x + k, D * j0, D * j1, D * j2, D * j3));
  if (img.lees_edwards) {
    const __m256d ny = _mm256_round_pd(_mm256_mul_pd(d[1], _mm256_set1_pd(img.inv_len[1])), kRound);
    d[1] = _mm256_sub_pd(d[1], _mm256_mul_pd(ny, _mm256_set1_pd(img.len[1])));
    d[0] = _mm256_sub_pd(d[0], _mm256_mul_pd(ny, _mm256_set1_pd(img.offset)));
  }
  __m256d d2 = _mm256_setzero_pd();
  for (int k = 0; k < D; ++k) {
    const __m256d n = _mm256_round_pd(_mm256_mul_pd(d[k], _mm256_set1_pd(img.image_inv[k])), kRound);
    d[k] = _mm256_sub_pd(d[k], _mm256_mul_pd(_mm256_set1_pd(img.image_len[k]), n));
    d2 = _mm256_add_pd(d2, _mm256_mul_pd(d[k], d[k]));
  }
  if (d2_out) *d2_out = d2;
  __m256d rs = _mm256_add_pd(four(r, i0, i1, i2, i3), four(r, j0, j1, j2, j3));
  if constexpr (Reach) rs = _mm256_add_pd(rs, _mm256_set1_pd(reach));
  return _mm256_movemask_pd(_mm256_cmp_pd(d2, _mm256_mul_pd(rs, rs), _CMP_LT_OQ));
}

// Four entries per iteration, then the scalar loop.
template <int D, bool Reach, class Sink>
[[gnu::target("avx2")]] int64_t avx2(const double* __restrict x, const double* __restrict r,
                                     const int32_t* __restrict pi, const int32_t* __restrict pj,
                                     const PeriodicImage<D> img, double reach, int64_t q0, int64_t q1,
                                     const Sink sink) {
  int64_t q = q0, c = 0;
  for (; q + 3 < q1; q += 4) {
    __m256d d[D];
    const int mask = four_separations<D, Reach>(x, r, pi, pj, img, reach, q, d);
    double dk[D][4];
    for (int k = 0; k < D; ++k) _mm256_storeu_pd(dk[k], d[k]);
    for (int e = 0; e < 4; ++e) {
      double de[D];
      for (int k = 0; k < D; ++k) de[k] = dk[k][e];
      c = sink(q + e, de, static_cast<uint8_t>((mask >> e) & 1), c);
    }
  }
  return scalar<D, Reach>(x, r, pi, pj, img, reach, q, q1, c, sink);
}

// Two entries per iteration, then the scalar loop.
template <int D, bool Reach, class Sink>
inline int64_t sse(const double* __restrict x, const double* __restrict r, const int32_t* __restrict pi,
                   const int32_t* __restrict pj, const PeriodicImage<D> img, double reach, int64_t q0, int64_t q1,
                   const Sink sink) {
  int64_t q = q0, c = 0;
  const __m128d zero = _mm_setzero_pd();
  for (; q + 1 < q1; q += 2) {
    const int64_t ia = pi[q], ja = pj[q], ib = pi[q + 1], jb = pj[q + 1];
    __m128d d[D];
    for (int k = 0; k < D; ++k)
      d[k] = _mm_sub_pd(_mm_loadh_pd(_mm_load_sd(x + D * ia + k), x + D * ib + k),
                        _mm_loadh_pd(_mm_load_sd(x + D * ja + k), x + D * jb + k));
    if (img.lees_edwards) {
      const __m128d ny = _mm_round_pd(_mm_mul_pd(d[1], _mm_set1_pd(img.inv_len[1])), kRound);
      d[1] = _mm_sub_pd(d[1], _mm_mul_pd(ny, _mm_set1_pd(img.len[1])));
      d[0] = _mm_sub_pd(d[0], _mm_mul_pd(ny, _mm_set1_pd(img.offset)));
    }
    __m128d d2 = zero;
    for (int k = 0; k < D; ++k) {
      const __m128d n = _mm_round_pd(_mm_mul_pd(d[k], _mm_set1_pd(img.image_inv[k])), kRound);
      d[k] = _mm_sub_pd(d[k], _mm_mul_pd(_mm_set1_pd(img.image_len[k]), n));
      d2 = _mm_add_pd(d2, _mm_mul_pd(d[k], d[k]));
    }
    __m128d rs = _mm_add_pd(_mm_loadh_pd(_mm_load_sd(r + ia), r + ib), _mm_loadh_pd(_mm_load_sd(r + ja), r + jb));
    if constexpr (Reach) rs = _mm_add_pd(rs, _mm_set1_pd(reach));
    const int mask = _mm_movemask_pd(_mm_cmplt_pd(d2, _mm_mul_pd(rs, rs)));
    double da[D], db[D];
    for (int k = 0; k < D; ++k) {
      _mm_store_sd(da + k, d[k]);
      _mm_storeh_pd(db + k, d[k]);
    }
    c = sink(q, da, static_cast<uint8_t>(mask & 1), c);
    c = sink(q + 1, db, static_cast<uint8_t>(mask >> 1), c);
  }
  return scalar<D, Reach>(x, r, pi, pj, img, reach, q, q1, c, sink);
}
#endif

}  // namespace scan_detail

// Reach: test against r_i + r_j + reach (else reach is ignored, and the test is the contact's).
// c = sink(q, const double* d, uint8_t within, c) is called once per entry, in order, from c = 0;
// returns the last c.
template <int D, bool Reach, class Sink>
inline int64_t scan_pairs(const double* __restrict x, const double* __restrict r, const int32_t* __restrict pi,
                          const int32_t* __restrict pj, const PeriodicImage<D> img, double reach, int64_t q0,
                          int64_t q1, const Sink sink) {
#if defined(__SSE4_1__)
  if (avx2_in_use()) return scan_detail::avx2<D, Reach>(x, r, pi, pj, img, reach, q0, q1, sink);
  return scan_detail::sse<D, Reach>(x, r, pi, pj, img, reach, q0, q1, sink);
#else
  return scan_detail::scalar<D, Reach>(x, r, pi, pj, img, reach, q0, q1, 0, sink);
#endif
}

}  // namespace silt::dem
