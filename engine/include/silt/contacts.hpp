// The contact network of a state: every touching pair of grains, for measurements, pictures and
// files (stress, coordination, force chains, VTK).
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "silt/periodic_image.hpp"
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

namespace contacts_detail {

template <int D, class F>
void for_each_contact_dim(const State& s, int64_t i0, int64_t i1, F&& f) {
  const PeriodicImage<D> img(s.box);  // (Box::nearest's images, by the inverse lengths)
  for (int64_t i = i0; i < i1; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      Contact c;
      c.i = i;
      c.j = s.pair_j[p];
      c.pair = p;
      for (int k = 0; k < D; ++k) c.d[k] = s.particle_x[D * i + k] - s.particle_x[D * c.j + k];
      img.apply(c.d);
      double d2 = 0;
      for (int k = 0; k < D; ++k) d2 += c.d[k] * c.d[k];
      const double reach = s.particle_r[i] + s.particle_r[c.j];
      if (!(d2 <= reach * reach * (1 + 1e-9))) continue;  // (no root for most listed pairs; it decides)
      c.dist = std::sqrt(d2);
      if (!(c.dist < reach) || c.dist == 0) continue;
      for (int k = 0; k < D; ++k) {
        c.f[k] = s.pair_f[D * p + k];
        c.fn += c.f[k] * c.d[k] / c.dist;
      }
      f(c);
    }
}

}  // namespace contacts_detail

// f(const Contact&) for every touching pair (|d| < r_i + r_j) of the grains i in [i0, i1) (the
// pairs listed with them), in pair order, without storing them (a measurement every few steps of
// a large bed need not allocate the network).
template <class F>
void for_each_contact_of(const State& s, int64_t i0, int64_t i1, F&& f) {
  if (s.dim == 2) contacts_detail::for_each_contact_dim<2>(s, i0, i1, f);
  else contacts_detail::for_each_contact_dim<3>(s, i0, i1, f);
}

// The same for every grain.
template <class F>
void for_each_contact(const State& s, F&& f) {
  for_each_contact_of(s, 0, s.n, f);
}

// The same, as a list.
std::vector<Contact> touching_contacts(const State& s);

}  // namespace silt
