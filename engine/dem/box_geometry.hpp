// Minimum-image arithmetic of the (possibly resizable) periodic box.
//
// Preconditions: every periodic length exceeds twice the largest interaction range, so that the
// nearest image is the only one within range (compile() checks it; the box controller stops the
// run before it shrinks below); and positions are wrapped into the box (kick_drift does it), so
// a separation is shorter than one box length and one compare per direction finds its image.
#pragma once

#include <cmath>

#include "silt/model.hpp"
#include "silt/vec.hpp"

namespace silt::dem {

template <int D>
struct PeriodicImage {
  explicit PeriodicImage(const Box& b) {
    for (int k = 0; k < D; ++k) {
      periodic[k] = b.periodic[k];
      len[k] = b.len[k];
      inv_len[k] = 1.0 / b.len[k];
      half[k] = 0.5 * b.len[k];
      image_len[k] = periodic[k] ? len[k] : 0.0;
      image_inv[k] = periodic[k] ? inv_len[k] : 0.0;
    }
  }
  // Replace a separation of two wrapped positions by its nearest periodic image.
  void apply(Vec<D>& d) const {
    for (int k = 0; k < D; ++k) {
      if (!periodic[k]) continue;
      if (d[k] > half[k])
        d[k] -= len[k];
      else if (d[k] < -half[k])
        d[k] += len[k];
    }
  }
  // Component k of the nearest image, without a branch: len = 0 in the open directions, and
  // rounding is one instruction (roundsd) with -fno-math-errno on x86-64-v2.
  double nearest(double d, int k) const { return d - image_len[k] * std::nearbyint(d * image_inv[k]); }
  // Nearest image of any separation (no wrapping precondition).
  void apply_any(Vec<D>& d) const {
    for (int k = 0; k < D; ++k)
      if (periodic[k]) d[k] -= len[k] * std::nearbyint(d[k] * inv_len[k]);
  }
  // Wrap a position into [lo, lo + len) in the periodic directions.
  template <class V>
  void wrap(V&& x, const Box& b) const {
    for (int k = 0; k < D; ++k) {
      if (!periodic[k] || (x[k] >= b.lo[k] && x[k] < b.lo[k] + len[k])) continue;
      x[k] -= std::floor((x[k] - b.lo[k]) * inv_len[k]) * len[k];
      if (x[k] >= b.lo[k] + len[k]) x[k] = b.lo[k];  // rounding at the upper edge
      if (x[k] < b.lo[k]) x[k] = b.lo[k];
    }
  }
  bool periodic[D];
  double len[D];
  double inv_len[D];
  double half[D];
  double image_len[D];  // len in periodic directions, 0 in open ones
  double image_inv[D];
};

}  // namespace silt::dem
