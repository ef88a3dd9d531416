// Stokes drag on every grain: a grain in a still viscous liquid at vanishing Reynolds number.
//
//   F = -6 pi eta r (v - u),   T = -8 pi eta r^3 omega      (Stokes 1851; Happel & Brenner 1965)
//
// with u the liquid's velocity at the grain: at rest, or following the affine flow of a deforming
// box (the velocity stored in particle_v is already relative to that flow). Disks in 2D are taken
// as the spheres of a monolayer (their drag per grain, not per unit length). Peyneau (2009)
// neglects it beside lubrication (sec. 1.5); LF_DEM adds it to every grain to keep isolated grains
// from making the resistance matrix singular, which is its use for the paste.
//
// Integrated with the grains' velocity Verlet from the half-step velocity, as the contact
// dashpots are: the velocity relaxes by the factor 1 - dt/tau per step, tau = m / (6 pi eta r) the
// grain's Stokes time, so the terminal velocity in a field g is exactly g tau, and the scheme is
// stable for dt < 2 tau (compile refuses dt > tau, where the decay would oscillate).
#pragma once

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::drag {

struct DragParams {
  double viscosity = 0;  // eta [Pa s] (steerable)
};

// Stokes' translational and rotational drag coefficients of a sphere of radius r.
inline double translational_coefficient(double eta, double r) { return 6.0 * std::numbers::pi * eta * r; }
inline double rotational_coefficient(double eta, double r) { return 8.0 * std::numbers::pi * eta * r * r * r; }

// (particle_v, particle_w, particle_r, particle_frozen) => (particle_f_drag, particle_t_drag)
void drag_forces(const Model& m, State& s, FieldId force, FieldId torque);

}  // namespace silt::drag
