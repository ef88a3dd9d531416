// The stages of a deforming periodic box: stress-controlled lengths (Peyneau 2009 eq. 3.11) and
// Lees-Edwards simple shear at imposed rate or stress (eq. 3.12). They enter the step in
// engine/graph/shear_stages.cpp.
#pragma once

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::shear {

// Whether the step has a box_kick stage: controlled box lengths or an imposed shear stress. It
// reads the pair forces at the end of every step, seen or not (State::boundary_seen).
inline bool box_stage_on(const Model& m) { return m.box_control.on || m.shear.stress_controlled; }

// (dt, box_stress, shear_stress, box_rate, shear_rate, box, le_displacement, shear_strain,
//  nbr_strain) => (box, box_rate, shear_rate, box_stretch, le_displacement, shear_strain,
//  nbr_strain, events.box_collapse)
// First half kick of the controlled lengths and of a stress-controlled shear rate, then their
// drift: the new lengths (box_stretch = L(t + dt) / L(t), 1 for the fixed ones) and the
// Lees-Edwards offset. The grains follow in dem::kick_drift. A controlled length below twice the
// interaction range raises box_collapse.
void box_drift(const Model& m, State& s);

// (dt, pair_f, particle_v, particle_x, inv_m, frozen, nbr_start, pair_j, box, box_rate,
//  shear_rate) => (box_stress, shear_stress, box_rate, shear_rate)
// Stresses along the controlled box lengths (and tau = -sigma_xy under stress-controlled shear),
// and the second half kicks (Peyneau eq. 3.11, 3.12).
void box_kick(const Model& m, State& s);
// Same stresses without the kick (the forces of the first state).
void box_stress(const Model& m, State& s);

// () => (shear_rate)
// The imposed shear rate as the model has it now, before the first forces: a state made before a
// change to it (the rate, or the viscosity or pressure of a viscous number) still holds the rate
// it was made with, which the first forces (and a paste's first solve) would otherwise use.
void impose_shear_rate(const Model& m, State& s);

}  // namespace silt::shear
