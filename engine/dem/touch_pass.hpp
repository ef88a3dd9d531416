// The first pass of contact_forces: which listed pairs touch.
//
// For the pairs [p0, p1) of a block, packs the touching ones (pair index and nearest-image
// separation d = x_i - x_j) into `tp` / `td` and returns how many; a pair that touched at the
// last evaluation and no longer does gets its force (and spring) cleared; pair_touch is
// updated. Two pairs go through the SSE registers at once (the same IEEE operations, in the same
// order, as the scalar loop, so both give the same bits); the scalar loop handles the last odd
// pair and builds without SSE4.1.
#pragma once

#include <cstdint>

#if defined(__SSE4_1__)
#include <smmintrin.h>
#endif

#include "core/small_vec.hpp"
#include "shear/periodic_image.hpp"

namespace silt::dem {

struct TouchArrays {
  const double* x;
  const double* r;
  const int32_t* pi;
  const int32_t* pj;
  uint8_t* touch;
  double* pf;
  double* hist;  // null without friction
};

namespace detail {

// Record pair p with separation d and touch flag `now` (0 or 1); returns the packed count.
template <int D>
inline int64_t record(const TouchArrays& a, int64_t p, const double* d, uint8_t now, int32_t* tp, double* td,
                      int64_t c) {
  // A pair just come apart: rare, so this branch is well predicted (the one that decides
  // whether to pack would not be, hence the unconditional stores and the count).
  if (a.touch[p] > now) {
    for (int k = 0; k < D; ++k) a.pf[D * p + k] = 0;
    if (a.hist)
      for (int k = 0; k < D; ++k) a.hist[D * p + k] = 0;
  }
  a.touch[p] = now;
  tp[c] = static_cast<int32_t>(p);
  for (int k = 0; k < D; ++k) td[D * c + k] = d[k];
  return c + now;
}

}  // namespace detail

// The arguments come by value: local copies that the stores cannot alias.
template <int D>
int64_t touch_pass(const TouchArrays a, const shear::PeriodicImage<D> img, int64_t p0, int64_t p1,
                   int32_t* __restrict tp, double* __restrict td) {
  using V = SVec<D>;
  const double* __restrict x = a.x;
  const double* __restrict r = a.r;
  int64_t c = 0, p = p0;
#if defined(__SSE4_1__)
  constexpr int kRound = _MM_FROUND_CUR_DIRECTION | _MM_FROUND_NO_EXC;  // std::nearbyint
  const __m128d zero = _mm_setzero_pd();
  for (; p + 1 < p1; p += 2) {
    const int64_t ia = a.pi[p], ja = a.pj[p], ib = a.pi[p + 1], jb = a.pj[p + 1];
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
    const int mask = _mm_movemask_pd(_mm_cmplt_pd(d2, _mm_mul_pd(rs, rs)));
    double da[D], db[D];
    for (int k = 0; k < D; ++k) {
      _mm_store_sd(da + k, d[k]);
      _mm_storeh_pd(db + k, d[k]);
    }
    c = detail::record<D>(a, p, da, static_cast<uint8_t>(mask & 1), tp, td, c);
    c = detail::record<D>(a, p + 1, db, static_cast<uint8_t>(mask >> 1), tp, td, c);
  }
#endif
  for (; p < p1; ++p) {
    const int64_t i = a.pi[p], j = a.pj[p];
    V d = V::load(x + D * i) - V::load(x + D * j);
    img.apply(d);
    const double rs = r[i] + r[j];
    double dd[D];
    d.store(dd);
    c = detail::record<D>(a, p, dd, static_cast<uint8_t>(d.squaredNorm() < rs * rs), tp, td, c);
  }
  return c;
}

}  // namespace silt::dem
