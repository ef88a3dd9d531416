// The touch pass, the first pass of contact_forces: which contact candidates touch, packed for
// the contact laws, with the pairs' touch flags kept up to date. The test is scan_pairs's
// (pair_scan.hpp); with AVX2 the touching pairs of each four entries are packed at once.
#pragma once

#include <cmath>
#include <cstdint>

#if defined(__SSE4_1__)
#include <immintrin.h>
#endif

#include "core/simd_level.hpp"
#include "dem/pair_scan.hpp"

namespace silt::dem {

struct TouchArrays {
  const double* x;
  const double* r;
  const int32_t* pp;  // entry q is pair pp[q]
  const int32_t* pi;  // of grains pi[q] and pj[q]
  const int32_t* pj;
  uint8_t* touch;
  double* pf;
  double* hist;  // null without friction
};

// A pair's touch flag after the test (`now`): a pair that touched at the last evaluation and
// no longer does gets its force (and spring) cleared. Rare, so this branch is well predicted.
template <int D>
[[gnu::always_inline]] inline void update_touch(const TouchArrays& a, int64_t p, uint8_t now) {
  if (a.touch[p] != now) {
    if (a.touch[p]) {
      for (int k = 0; k < D; ++k) a.pf[D * p + k] = 0;
      if (a.hist)
        for (int k = 0; k < D; ++k) a.hist[D * p + k] = 0;
    }
    a.touch[p] = now;
  }
}

// Entry c of the columns of separations: the D components, |d| and 1 / |d| (the square root
// and the division of the normal law, done here, four pairs at a time with AVX2).
template <int D, class Columns>
[[gnu::always_inline]] inline void store_separation(const Columns& td, int64_t c, const double* d) {
  double d2 = 0;
  for (int k = 0; k < D; ++k) {
    td[k][c] = d[k];
    d2 += d[k] * d[k];
  }
  const double dist = std::sqrt(d2);
  td[D][c] = dist;
  td[D + 1][c] = 1.0 / dist;
}

// What the touch pass does with each tested entry (a sink of scan_pairs): update the pair's
// flag, store its index and separation at the packed position c, whether it touches or not
// (which pairs touch follows no pattern: a branch would mispredict), and count it if it does.
template <int D>
struct TouchSink {
  TouchArrays a;
  int32_t* tp;
  double* td[D + 2];
  int64_t operator()(int64_t q, const double* d, uint8_t now, int64_t c) const {
    const int64_t p = a.pp[q];
    update_touch<D>(a, p, now);
    tp[c] = static_cast<int32_t>(p);
    store_separation<D>(td, c, d);
    return c + now;
  }
};

template <int D>
TouchSink<D> touch_sink(const TouchArrays& a, int32_t* tp, double* const* td) {
  TouchSink<D> sink{a, tp, {}};
  for (int k = 0; k < D + 2; ++k) sink.td[k] = td[k];
  return sink;
}

#if defined(__SSE4_1__)
namespace scan_detail {

// Left packing of four lanes: for a 4-bit mask, the indices of the lanes set, in order, as
// 32-bit lane indices for _mm256_permutevar8x32 (of doubles: two per lane; of 32-bit integers).
struct LeftPack {
  alignas(32) int32_t of_double[16][8];
  alignas(32) int32_t of_int[16][8];
};
constexpr LeftPack make_left_pack() {
  LeftPack t{};
  for (int m = 0; m < 16; ++m) {
    int n = 0;
    for (int e = 0; e < 4; ++e)
      if ((m >> e) & 1) {
        t.of_double[m][2 * n] = 2 * e;
        t.of_double[m][2 * n + 1] = 2 * e + 1;
        t.of_int[m][n] = e;
        ++n;
      }
  }
  return t;
}
inline constexpr LeftPack kLeftPack = make_left_pack();

[[gnu::target("avx2"), gnu::always_inline]] inline __m256d left_pack(__m256d v, __m256i lanes) {
  return _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), lanes));
}

// The touch pass four entries at a time: the touching ones of each four are packed with one
// permutation per column (no branch, no per-entry stores).
template <int D>
[[gnu::target("avx2")]] int64_t touch_avx2(const TouchArrays a, const PeriodicImage<D> img, int64_t q0, int64_t q1,
                                           int32_t* __restrict tp, double* const* td) {
  double* __restrict tdk[D + 2];
  for (int k = 0; k < D + 2; ++k) tdk[k] = td[k];
  int64_t q = q0, c = 0;
  for (; q + 3 < q1; q += 4) {
    __m256d d[D];
    __m256d d2;
    const int mask = four_separations<D, false>(a.x, a.r, a.pi, a.pj, img, 0.0, q, d, &d2);
    for (int e = 0; e < 4; ++e) update_touch<D>(a, a.pp[q + e], static_cast<uint8_t>((mask >> e) & 1));
    const __m256i pd = _mm256_load_si256(reinterpret_cast<const __m256i*>(kLeftPack.of_double[mask]));
    const __m256d dist = _mm256_sqrt_pd(d2);
    for (int k = 0; k < D; ++k) _mm256_storeu_pd(tdk[k] + c, left_pack(d[k], pd));
    _mm256_storeu_pd(tdk[D] + c, left_pack(dist, pd));
    _mm256_storeu_pd(tdk[D + 1] + c, left_pack(_mm256_div_pd(_mm256_set1_pd(1.0), dist), pd));
    const __m256i pairs = _mm256_castsi128_si256(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a.pp + q)));
    const __m256i pk = _mm256_load_si256(reinterpret_cast<const __m256i*>(kLeftPack.of_int[mask]));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(tp + c),
                     _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(pairs, pk)));
    c += __builtin_popcount(static_cast<unsigned>(mask));
  }
  return scalar<D, false>(a.x, a.r, a.pi, a.pj, img, 0.0, q, q1, c, touch_sink<D>(a, tp, td));
}

}  // namespace scan_detail
#endif

// The touch pass over the candidate entries [q0, q1) of a block: packs the touching pairs into
// `tp` (pair index) and `td` (D + 2 columns: the separation's components, its norm and the
// inverse of the norm; store_separation) and returns how many;
// a pair that touched at the last evaluation and no longer does gets its force (and spring)
// cleared; pair_touch is updated. The arguments come by value: local copies that the stores
// cannot alias.
template <int D>
int64_t touch_pass(const TouchArrays a, const PeriodicImage<D> img, int64_t q0, int64_t q1, int32_t* __restrict tp,
                   double* const* td) {
#if defined(__SSE4_1__)
  if (avx2_in_use()) return scan_detail::touch_avx2<D>(a, img, q0, q1, tp, td);
#endif
  return scan_pairs<D, false>(a.x, a.r, a.pi, a.pj, img, 0.0, q0, q1, touch_sink<D>(a, tp, td));
}

}  // namespace silt::dem
