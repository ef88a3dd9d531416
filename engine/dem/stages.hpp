// The DEM stages of a step. Each is `void stage(const Model&, State&)`; the first comment line
// of each is its contract: (what it reads) => (what it writes). They are wired together in
// engine/graph/step_graph.cpp.
#pragma once

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::dem {

// (particle_v, particle_f, particle_t, particle_x, box_stress, shear_stress) => (particle_v,
//  particle_w, particle_x, particle_disp, box, box_rate, shear_rate, le_displacement,
//  nbr_max_disp, nbr_step_disp, nbr_strain)
// First half kick v += dt/2 a, drift x += dt v (plus the affine flow of a deforming or sheared
// box), wrap into the periodic box (Lees-Edwards shifted), and the largest displacement since
// the last neighbour build.
void kick_drift(const Model& m, State& s);

// (particle_x, particle_r, nbr_max_disp, nbr_step_disp, box) => (nbr_start, pair_i, pair_j,
//  pair_hist, pair_f, pair_touch, particle_disp, nbr_strain)
// Rebuild the half Verlet list (cell list, pairs within r_i + r_j + skin) only when a grain
// moved more than skin/2 since the last build; tangential histories of surviving pairs are kept.
// Then re-select the contact candidates (contact_candidates.hpp) when they may have gone stale.
void update_neighbors(const Model& m, State& s);

// (particle_x, particle_v, particle_w, pair_i, pair_j, pair_hist, pair_touch) => (pair_f,
//  pair_hist, pair_touch, particle_f, particle_t, alarm_overlap)
// Normal law + tangential spring for every listed pair; the force on i stored per pair, and the
// sum over all pairs of each grain in particle_f / particle_t (in the order of the pair schedule).
void contact_forces(const Model& m, State& s);

// (particle_x, particle_v, particle_w, wall_hist) => (wall_f, particle_t_wall,
//  wall_hist, alarm_overlap)
void wall_forces(const Model& m, State& s);

// (particle_f, particle_t [pair sums], wall_f, particle_t_wall) => (particle_f, particle_t,
//  particle_v, particle_w, alarm_nonfinite)
// Add the wall forces, then the second half kick.
void kick(const Model& m, State& s);
// Same sum without the kick, to start a run with the forces of t = 0.
void add_wall_forces(const Model& m, State& s);

}  // namespace silt::dem
