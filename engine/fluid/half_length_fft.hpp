// The discrete Fourier transform of a real line of even length n through a complex transform of
// length N = n / 2 (Press et al., Numerical Recipes, 3rd ed., §12.3.2): the line read as N complex
// values z_k = x_2k + i x_2k+1, transformed (Z = DFT_N z), then split into the spectra of the even
// and odd points, E_k = (Z_k + conj Z_N-k) / 2 and O_k = (Z_k - conj Z_N-k) / 2i, and joined:
// X_k = E_k + W^k O_k, X_N-k = conj(E_k - W^k O_k), with W = exp(-2 pi i / n).
//
// In place, in the packed order of the fast solver: X_0, X_N (both real), then Re X_k, Im X_k for
// k = 1 .. N - 1, n values. The scale is FFTW's: forward unnormalised, and the backward pair
// (unpack_spectrum, then the backward complex transform) gives n x. FFTW's complex codelets are
// vectorised where its real-to-complex ones are not, so the pair runs two to three times as fast.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numbers>
#include <vector>

#include "core/simd_level.hpp"

namespace silt::fluid {

// cos and -sin of 2 pi k / n for k = 0 .. n / 4, interleaved: W^k.
std::vector<double> half_length_twiddles(int64_t n);

// One line (lanes = 1), whose pairs no loop over lanes can vectorise: the pairs a chunk at a time,
// the values at N - k copied in k's order into a buffer, f run over the chunk as one loop, and the
// buffer copied back. At k = N / 2 (a and b the same values) f's a wins, as below: that value is
// not copied back.
template <class F>
inline void for_each_mode_pair_of_line(double* v, int64_t n, const double* w, F&& f) {
  const int64_t N = n / 2;
  const double r0 = v[0], i0 = v[1];
  v[0] = r0 + i0;
  v[1] = r0 - i0;
  constexpr int64_t kChunk = 32;
  double mirror[2 * kChunk];
  for (int64_t k0 = 1; 2 * k0 <= N; k0 += kChunk) {
    const int64_t count = std::min(kChunk, N / 2 - k0 + 1);
    for (int64_t l = 0; l < count; ++l) {
      mirror[2 * l] = v[2 * (N - k0 - l)];
      mirror[2 * l + 1] = v[2 * (N - k0 - l) + 1];
    }
    double* a = v + 2 * k0;
    const double* wk = w + 2 * k0;
    SILT_IVDEP
    for (int64_t l = 0; l < count; ++l) f(a + 2 * l, mirror + 2 * l, wk[2 * l], wk[2 * l + 1]);
    for (int64_t l = 0; l < count; ++l) {
      if (2 * (k0 + l) == N) continue;
      v[2 * (N - k0 - l)] = mirror[2 * l];
      v[2 * (N - k0 - l) + 1] = mirror[2 * l + 1];
    }
  }
}

// Both below work on `lanes` lines side by side (complex k of line l at v + cs k + 2 l, cs >= 2
// lanes the values of a row, padding included): one line (lanes = 1, cs = 2) or a block whose
// lines are interleaved, each loop over the lines contiguous.
// Entries 0 and 1 of each line become their sum and difference; then f(a, b, W^k) for the pairs of
// complex values k and N - k of each line, k = 1 .. N / 2 (at k = N / 2 a and b are the same
// values, which f reads before it writes).
template <class F>
inline void for_each_mode_pair(double* v, int64_t n, const double* w, int64_t lanes, int64_t cs, F&& f) {
  if (lanes == 1) return for_each_mode_pair_of_line(v, n, w, f);
  const int64_t N = n / 2;
  SILT_IVDEP
  for (int64_t l = 0; l < lanes; ++l) {
    const double r0 = v[2 * l], i0 = v[2 * l + 1];
    v[2 * l] = r0 + i0;
    v[2 * l + 1] = r0 - i0;
  }
  for (int64_t k = 1; 2 * k <= N; ++k) {
    double* a = v + k * cs;
    double* b = v + (N - k) * cs;
    const double wr = w[2 * k], wi = w[2 * k + 1];
    SILT_IVDEP
    for (int64_t l = 0; l < lanes; ++l) f(a + 2 * l, b + 2 * l, wr, wi);
  }
}

// After the forward complex transform of the N values of each line: the packed spectra
// (entries 0 and 1: X_0 = Re Z_0 + Im Z_0 and X_N = Re Z_0 - Im Z_0).
inline void pack_spectrum(double* v, int64_t n, const double* w, int64_t lanes = 1, int64_t cs = 2) {
  for_each_mode_pair(v, n, w, lanes, cs, [](double* a, double* b, double wr, double wi) {
    const double ar = a[0], ai = a[1], br = b[0], bi = -b[1];  // Z_k, conj Z_N-k
    const double er = 0.5 * (ar + br), ei = 0.5 * (ai + bi);
    const double orr = 0.5 * (ai - bi), oi = -0.5 * (ar - br);  // (Z_k - conj Z_N-k) / 2i
    // W^k O_k. Every product added (wr orr + (-wi) oi is wr orr - wi oi to the bit): GCC 12
    // fuses a product subtracted in one lane and added in the next into a fused multiply-add
    // (vfmsubadd) where the processor has AVX-512, -ffp-contract=off notwithstanding.
    const double nwi = -wi;
    const double tr = wr * orr + nwi * oi, ti = wr * oi + wi * orr;
    b[0] = er - tr;
    b[1] = ti - ei;
    a[0] = er + tr;
    a[1] = ei + ti;
  });
}

// Before the backward complex transform: the N complex values of each line whose transform is
// n x (entries 0 and 1: Z_0 = X_0 + X_N + i (X_0 - X_N)).
inline void unpack_spectrum(double* v, int64_t n, const double* w, int64_t lanes = 1, int64_t cs = 2) {
  for_each_mode_pair(v, n, w, lanes, cs, [](double* a, double* b, double wr, double w_im) {
    const double wi = -w_im;                                   // conj W^k
    const double ar = a[0], ai = a[1], br = b[0], bi = -b[1];  // X_k, conj X_N-k
    const double er = ar + br, ei = ai + bi, dr = ar - br, di = ai - bi;
    // (X_k - conj X_N-k) conj W^k; every product added, as in pack_spectrum.
    const double orr = dr * wr + di * w_im, oi = dr * wi + di * wr;
    // Z_k = E + i O, Z_N-k = conj E + i conj O.
    b[0] = er + oi;
    b[1] = orr - ei;
    a[0] = er - oi;
    a[1] = ei + orr;
  });
}

// The cosine transform (DCT-II, FFTW's REDFT10: Y_k = 2 sum_j x_j cos(pi k (j + 1/2) / n)) of a
// line of even length n through the real one (Makhoul 1980): the points reordered as v_r =
// x_source(r) (cosine_source: the even points forward, then the odd ones backward), V = DFT_n v in
// the packed order above, then Y_k = 2 Re(exp(-i pi k / 2n) V_k) for k and n - k from V_k. The
// spectrum stays in the packed places: Y_0 at 0, Y_n/2 at 1, Y_k at 2k and Y_n-k at 2k + 1
// (cosine_mode). The sine transform (DST-II, RODFT10) is the cosine one of (-1)^j x_j with the
// modes reversed (mode n - 1 - q where the cosine transform has q). Backward: the same steps
// reversed give 2n x, as FFTW's REDFT01 (RODFT01) after REDFT10 (RODFT10).

// Point of the line at place r of the reordered one.
inline int64_t cosine_source(int64_t r, int64_t n) { return 2 * r < n ? 2 * r : 2 * (n - r) - 1; }
// Cosine mode at place p of the packed spectrum.
inline int64_t cosine_mode(int64_t p, int64_t n) {
  if (p < 2) return p == 0 ? 0 : n / 2;
  return p % 2 == 0 ? p / 2 : n - p / 2;
}
// cos and sin of pi k / 2n for k = 0 .. n / 2, interleaved.
std::vector<double> cosine_twiddles(int64_t n);

// After pack_spectrum (scale 2): the cosine spectra. Before unpack_spectrum (scale 1): twice the
// real spectra whose cosine spectra these are (the rotation is its own inverse):
// Y_0 = scale V_0, Y_n/2 = sqrt 2 V_n/2 (2 cos(pi / 4)), and for the pair of places of V_k,
// (Y_k, Y_n-k) = scale (c V_r + s V_i, s V_r - c V_i) with c, s = cos, sin(pi k / 2n).
inline void rotate_cosine_spectrum(double* v, int64_t n, const double* c, double scale, int64_t lanes = 1,
                                   int64_t cs = 2) {
  const int64_t N = n / 2;
  SILT_IVDEP
  for (int64_t l = 0; l < lanes; ++l) {
    v[2 * l] *= scale;
    v[2 * l + 1] *= std::numbers::sqrt2;
  }
  // (vr, vi) at a rotated; every product added, as in pack_spectrum.
  const auto rotate = [scale](double* a, double ck, double sk) {
    const double nck = -ck, vr = a[0], vi = a[1];
    a[0] = scale * (ck * vr + sk * vi);
    a[1] = scale * (sk * vr + nck * vi);
  };
  if (lanes == 1) {  // one line: the loop over k vectorises
    SILT_IVDEP
    for (int64_t k = 1; k < N; ++k) rotate(v + 2 * k, c[2 * k], c[2 * k + 1]);
    return;
  }
  for (int64_t k = 1; k < N; ++k) {
    double* a = v + k * cs;
    const double ck = c[2 * k], sk = c[2 * k + 1];
    SILT_IVDEP
    for (int64_t l = 0; l < lanes; ++l) rotate(a + 2 * l, ck, sk);
  }
}
inline void cosine_from_spectrum(double* v, int64_t n, const double* c, int64_t lanes = 1, int64_t cs = 2) {
  rotate_cosine_spectrum(v, n, c, 2.0, lanes, cs);
}
inline void spectrum_from_cosine(double* v, int64_t n, const double* c, int64_t lanes = 1, int64_t cs = 2) {
  rotate_cosine_spectrum(v, n, c, 1.0, lanes, cs);
}

// The sine transform of interior faces (DST-I, FFTW's RODFT00, Y_k = 2 sum_j x_j sin(pi (j + 1)
// (k + 1) / N) for m = N - 1 points, N even) through the real transform of N values (Numerical
// Recipes §12.4.1): f_0 = 0, f_j = x_j-1; y_j = sin(pi j / N) (f_j + f_N-j) + (f_j - f_N-j) / 2, whose
// real spectrum Y gives F_2k = -Im Y_k and F_2k+1 = F_2k-1 + Re Y_k (F_1 = Re Y_0 / 2), F_q the
// sums sum_j f_j sin(pi j q / N). Place r of a line's N places is at (r / 2) cs + r % 2 (cs >= 2
// lanes, as above), lane l 2l further. face_sine_prepare takes the N places (place 0 zero) to y;
// face_sine_finish takes the packed spectrum of y to 2 F_q at place q - 1, natural order, place
// N - 1 zero: FFTW's Y_k at place k. The transform is its own inverse up to 2N.
std::vector<double> face_sine_table(int64_t N);  // sin(pi j / N), j = 0 .. N / 2

inline void face_sine_prepare(double* v, int64_t N, const double* s, int64_t lanes = 1, int64_t cs = 2) {
  auto at = [cs](int64_t r) { return (r >> 1) * cs + (r & 1); };
  SILT_IVDEP
  for (int64_t l = 0; l < lanes; ++l) v[2 * l] = 0;
  for (int64_t j = 1; 2 * j <= N; ++j) {
    double* a = v + at(j);
    double* b = v + at(N - j);
    const double sj = s[j];
    SILT_IVDEP
    for (int64_t l = 0; l < lanes; ++l) {
      const double fa = a[2 * l], fb = b[2 * l];
      const double sym = sj * (fa + fb), anti = 0.5 * (fa - fb);
      a[2 * l] = sym + anti;
      b[2 * l] = sym - anti;  // at j = N / 2 (a = b) anti is 0
    }
  }
}

inline void face_sine_finish(double* v, int64_t N, int64_t lanes = 1, int64_t cs = 2) {
  // Place 0 holds Re Y_0 = 2 F_1 already; each step reads 2 F_2k-1 where the one before left it.
  for (int64_t k = 1; 2 * k < N; ++k) {
    double* pair = v + k * cs;          // places 2k, 2k + 1: Re Y_k, Im Y_k
    double* before = v + (k - 1) * cs;  // places 2k - 2 (2 F_2k-1) and 2k - 1
    SILT_IVDEP
    for (int64_t l = 0; l < lanes; ++l) {
      const double re = pair[2 * l], im = pair[2 * l + 1];
      before[2 * l + 1] = -2 * im;           // 2 F_2k at place 2k - 1
      pair[2 * l] = before[2 * l] + 2 * re;  // 2 F_2k+1 at place 2k
    }
  }
  SILT_IVDEP
  for (int64_t l = 0; l < lanes; ++l) v[(N - 1) / 2 * cs + 1 + 2 * l] = 0;  // place N - 1
}

}  // namespace silt::fluid
