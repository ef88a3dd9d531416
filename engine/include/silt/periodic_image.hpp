// Minimum-image arithmetic of the (possibly resizable, possibly sheared) periodic box, for the
// particle kernels: Box::nearest with the constants hoisted and no branch per component.
//
// Preconditions: every periodic length exceeds twice the largest interaction range, so that the
// nearest image is the only one within range (compile() checks it; the box controller stops the
// run before it shrinks below).
#pragma once

#include <cmath>

#include "silt/model.hpp"
#include "silt/vec.hpp"

namespace silt {

template <int D>
struct PeriodicImage {
  explicit PeriodicImage(const Box& b) : lees_edwards(b.lees_edwards), offset(b.le_offset) {
    for (int k = 0; k < D; ++k) {
      periodic[k] = b.periodic[k];
      len[k] = b.len[k];
      inv_len[k] = 1.0 / b.len[k];
      // len = 0 in the open directions: rounding then changes nothing, and needs no branch
      // (nearbyint is one instruction, roundsd, with -fno-math-errno on x86-64-v2).
      image_len[k] = periodic[k] ? len[k] : 0.0;
      image_inv[k] = periodic[k] ? inv_len[k] : 0.0;
    }
  }
  // Nearest image of a separation d (Eigen or SVec).
  template <class V>
  void apply(V& d) const {
    if (lees_edwards) {
      const double ny = std::nearbyint(d[1] * inv_len[1]);
      d[1] -= ny * len[1];
      d[0] -= ny * offset;
    }
    for (int k = 0; k < D; ++k) d[k] -= image_len[k] * std::nearbyint(d[k] * image_inv[k]);
  }
  // Wrap a position into the box in the periodic directions; under Lees-Edwards a grain leaving
  // through y enters the other side shifted along x by the offset (its velocity relative to the
  // shear flow is unchanged). y is settled here, with its shift: rounding can put a grain a hair
  // below lo_y onto the upper edge lo_y + L_y, which is the image one more period down (y = lo_y,
  // x shifted once more), or leave it a hair below lo_y, which is the same image; the generic
  // loop below would wrap those without the shift.
  template <class V>
  void wrap(V&& x, const Box& b) const {
    if (lees_edwards && !(x[1] >= b.lo[1] && x[1] < b.lo[1] + len[1])) {
      double ny = std::floor((x[1] - b.lo[1]) * inv_len[1]);
      x[1] -= ny * len[1];
      if (x[1] >= b.lo[1] + len[1]) {
        x[1] = b.lo[1];
        ny += 1;
      }
      if (x[1] < b.lo[1]) x[1] = b.lo[1];
      x[0] -= ny * offset;
    }
    for (int k = 0; k < D; ++k) {
      if (!periodic[k] || (x[k] >= b.lo[k] && x[k] < b.lo[k] + len[k])) continue;
      x[k] -= std::floor((x[k] - b.lo[k]) * inv_len[k]) * len[k];
      if (x[k] >= b.lo[k] + len[k]) x[k] = b.lo[k];  // rounding at the upper edge
      if (x[k] < b.lo[k]) x[k] = b.lo[k];
    }
  }
  bool lees_edwards;
  double offset;
  bool periodic[D];
  double len[D];
  double inv_len[D];
  double image_len[D];
  double image_inv[D];
};

}  // namespace silt
