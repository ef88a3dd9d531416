// Slab-averaged velocity profile across the gradient direction (Peyneau 2009 sec. 3.2.1): the
// box is cut into slabs normal to y, and a grain counts, with its full velocity (the affine
// shear flow gammadot (y - lo_y) plus its own), in every slab it overlaps.
#include <algorithm>
#include <cmath>

#include "silt/observables.hpp"

namespace silt {

VelocityProfile velocity_profile(const Model& m, const State& s, int n_slabs) {
  VelocityProfile p;
  n_slabs = std::max(1, n_slabs);
  const int D = m.dim;
  const double lo = s.box.lo[1], len = s.box.len[1], h = len / n_slabs;
  p.y.resize(n_slabs);
  p.vx.assign(n_slabs, 0.0);
  p.count.assign(n_slabs, 0);
  for (int k = 0; k < n_slabs; ++k) p.y[k] = (k + 0.5) / n_slabs;
  const bool affine = m.shear.on;
  for (int64_t i = 0; i < s.n; ++i) {
    if (s.particle_frozen[i]) continue;
    const double y = s.particle_x[D * i + 1] - lo, r = s.particle_r[i];
    const double vx = s.particle_v[D * i] + (affine ? s.shear_rate * y : 0.0);
    const int first = static_cast<int>(std::floor((y - r) / h)), last = static_cast<int>(std::floor((y + r) / h));
    for (int k = first; k <= last; ++k) {
      const int slab = ((k % n_slabs) + n_slabs) % n_slabs;
      // A periodic image seen through the sheared boundary moves gammadot L_y faster or slower.
      const double shift = affine ? s.shear_rate * len * static_cast<double>((k - slab) / n_slabs) : 0.0;
      p.vx[slab] += vx - shift;
      ++p.count[slab];
    }
  }
  for (int k = 0; k < n_slabs; ++k)
    if (p.count[k]) p.vx[k] /= static_cast<double>(p.count[k]);
  return p;
}

}  // namespace silt
