// The contact network of a state: every touching pair of grains, for measurements, pictures and
// files (stress, coordination, force chains, VTK).
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "silt/state.hpp"

namespace silt {

struct Contact {
  int64_t i = 0, j = 0;       // grain indices
  int64_t pair = 0;           // index in the pair arrays
  std::array<double, 3> d{};  // x_i - x_j, nearest periodic image (z = 0 in 2D)
  double dist = 0;            // |d|
  std::array<double, 3> f{};  // force on i from j
  double fn = 0;              // normal force f . d / |d| (> 0 repulsive)
};

// f(const Contact&) for every touching pair (|d| < r_i + r_j), in pair order, without storing
// them (a measurement every few steps of a large bed need not allocate the network).
template <class F>
void for_each_contact(const State& s, F&& f) {
  const int D = s.dim;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      Contact c;
      c.i = i;
      c.j = s.pair_j[p];
      c.pair = p;
      double d2 = 0;
      for (int k = 0; k < D; ++k) c.d[k] = s.particle_x[D * i + k] - s.particle_x[D * c.j + k];
      s.box.nearest(c.d.data(), D);
      for (int k = 0; k < D; ++k) d2 += c.d[k] * c.d[k];
      c.dist = std::sqrt(d2);
      if (!(c.dist < s.particle_r[i] + s.particle_r[c.j]) || c.dist == 0) continue;
      for (int k = 0; k < D; ++k) {
        c.f[k] = s.pair_f[D * p + k];
        c.fn += c.f[k] * c.d[k] / c.dist;
      }
      f(c);
    }
}

// The same, as a list.
std::vector<Contact> touching_contacts(const State& s);

}  // namespace silt
