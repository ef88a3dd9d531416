// The arguments of the grain passes of velocity Verlet (integrate.cpp), shared with their
// vector kernels (grain_pass_avx2.hpp). They are passed by value: a local copy that the stores
// to the arrays cannot alias, so the loops keep them in registers.
#pragma once

#include <cstdint>

#include "silt/events.hpp"
#include "silt/periodic_image.hpp"
#include "silt/state.hpp"

namespace silt::dem::grain_pass {

// Affine: the box deforms (stress control or shear). The grains are carried by the affine flow
// x -> lo + lambda (x - lo) and v_x += gammadot (y - lo_y), and move relative to it with their
// stored velocity c (the flow is not stored in particle_v). For the lengths this is Peyneau's
// eq. 3.10 without its coupling terms, negligible for dissipative grains at small I. For the
// shear the motion stays Newton's: the velocity u = c + gammadot (y - lo_y) e_x obeys
// m du/dt = F, so dc_x/dt = F_x/m - gammadot c_y (the SLLOD equations of Evans & Morriss
// 1990, exact for simple shear at a constant rate; Peyneau integrates u itself; when the rate
// changes, the grains follow the new flow at once, as for the lengths). A kick takes the c_y of
// the instant of its force: c_y(t) in the first half kick, c_y(t + dt) in the second.
template <int D>
struct DriftArgs {
  double dt, h, gd;
  EventSlot* nonfinite;
  double lo[D], g[D], lambda[D];
  PeriodicImage<D> img;
  Box box;
  double* x;
  double* v;
  double* w;
  double* disp;
  const double* f;
  const double* t;
  const double* inv_m;
  const double* inv_i;
  const uint8_t* frozen;
};

// At most this many force (or torque) sources besides the pair sums.
constexpr int kMaxSources = 8;

template <int D>
struct KickArgs {
  double h, gd;  // half step, shear rate (0 without shear)
  double g[D];
  int n_force, n_torque;
  const double* force_src[kMaxSources];  // per grain: force_items[k] vectors of D
  int force_items[kMaxSources];          // 1, or W for a per grain-wall source
  const double* torque_src[kMaxSources];
  const double* inv_m;
  const double* inv_i;
  const uint8_t* frozen;
  double* force;
  double* torq;
  double* v;
  double* w;
  EventSlot* nonfinite;
};

}  // namespace silt::dem::grain_pass
