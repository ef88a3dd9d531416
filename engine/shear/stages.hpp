// The stages of a deforming periodic box: stress-controlled lengths (Peyneau 2009 eq. 3.11) and
// Lees-Edwards simple shear at imposed rate or stress (eq. 3.12). Wired in
// engine/graph/step_graph.cpp; the grains' affine drift is in dem::kick_drift, which calls
// box_drift first.
#pragma once

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::shear {

// Whether the step has a box_kick stage: controlled box lengths or an imposed shear stress. It
// reads the pair forces at the end of every step, seen or not (State::boundary_seen).
inline bool box_stage_on(const Model& m) { return m.box_control.on || m.shear.stress_controlled; }

// (box_stress, shear_stress, box_rate, shear_rate, box) => (box, box_rate, shear_rate,
//  le_displacement, shear_strain, nbr_strain)
// First half kick of the controlled lengths and of a stress-controlled shear rate, then their
// drift: the new lengths, the Lees-Edwards offset. lambda[k] = L_k(t + dt) / L_k(t), 1 for the
// fixed lengths (the caller initialises it). Called by dem::kick_drift.
void box_drift(const Model& m, State& s, double* lambda);

// (pair_f, particle_v, particle_x) => (box_stress, shear_stress, box_rate, shear_rate)
// Stresses along the controlled box lengths (and tau = -sigma_xy under stress-controlled shear),
// and the second half kicks (Peyneau eq. 3.11, 3.12).
void box_kick(const Model& m, State& s);
// Same stresses without the kick.
void box_stress(const Model& m, State& s);

}  // namespace silt::shear
