// Slab-averaged velocity profile (Peyneau 2009 sec. 3.2.1): the box is cut into slabs normal to
// an axis, and a grain counts, with its full velocity (the affine shear flow
// gammadot (y - lo_y) included), in every slab it overlaps. Along a periodic axis a grain that
// crosses the boundary counts on both sides (under Lees-Edwards, its image seen across y moves
// gammadot L_y faster or slower); along an open one the slabs span the domain.
#include <algorithm>
#include <cmath>

#include "silt/observables.hpp"

namespace silt {

VelocityProfile velocity_profile(const Model& m, const State& s, int n_slabs, int axis, int component) {
  VelocityProfile p;
  n_slabs = std::max(1, n_slabs);
  const int D = m.dim;
  const double lo = s.box.lo[axis], len = s.box.len[axis], h = len / n_slabs;
  const bool periodic = s.box.periodic[axis];
  p.y.resize(n_slabs);
  p.vx.assign(n_slabs, 0.0);
  p.count.assign(n_slabs, 0);
  for (int k = 0; k < n_slabs; ++k) p.y[k] = (k + 0.5) / n_slabs;
  const bool affine = m.shear.on && component == 0;
  for (int64_t i = 0; i < s.n; ++i) {
    if (s.particle_frozen[i]) continue;
    const double y = s.particle_x[D * i + axis] - lo, r = s.particle_r[i];
    const double v =
        s.particle_v[D * i + component] + (affine ? s.shear_rate * (s.particle_x[D * i + 1] - s.box.lo[1]) : 0.0);
    // The slabs it overlaps, in double first: a grain of a failed run (a position or a radius not
    // finite, or far outside the box) is not counted, and a grain larger than a periodic box
    // counts once in each slab, so that the indices stay small integers.
    double lo_k = std::floor((y - r) / h), hi_k = std::floor((y + r) / h);
    if (!periodic) {
      lo_k = std::max(lo_k, 0.0);
      hi_k = std::min(hi_k, n_slabs - 1.0);
    }
    if (!(std::abs(lo_k) < 1e9 && std::abs(hi_k) < 1e9)) continue;
    hi_k = std::min(hi_k, lo_k + n_slabs - 1);
    const int first = static_cast<int>(lo_k), last = static_cast<int>(hi_k);
    for (int k = first; k <= last; ++k) {
      const int slab = ((k % n_slabs) + n_slabs) % n_slabs;
      // A periodic image seen through the sheared boundary moves gammadot L_y faster or slower.
      const bool sheared_image = affine && axis == 1 && m.box.lees_edwards;
      const double shift = sheared_image ? s.shear_rate * len * static_cast<double>((k - slab) / n_slabs) : 0.0;
      p.vx[slab] += v - shift;
      ++p.count[slab];
    }
  }
  for (int k = 0; k < n_slabs; ++k)
    if (p.count[k]) p.vx[k] /= static_cast<double>(p.count[k]);
  return p;
}

}  // namespace silt
