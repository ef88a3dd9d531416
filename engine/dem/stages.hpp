// The DEM stages. Each is `void stage(const Model&, State&, ...)`; the first comment line of each
// is its contract: (what it reads) => (what it writes). They enter the step in
// engine/graph/dem_stages.cpp, which declares the same sets as field ids.
#pragma once

#include <array>
#include <functional>

#include "core/owned.hpp"
#include "core/workspace.hpp"
#include "dem/workspace.hpp"
#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::dem {

// A pass over the grains [b, e) of one block, returning its largest squared displacements
// (kick_and_next_drift).
using GrainBlockPass = std::function<std::array<double, 2>(int64_t b, int64_t e)>;

// (dt, box, box_stretch, shear_rate, particle_v, particle_w, particle_f, particle_t, particle_x,
//  particle_disp, inv_m, inv_i, frozen) => (particle_v, particle_w, particle_x, particle_disp,
//  nbr_max_disp, nbr_step_disp)
// First half kick v += dt/2 a, drift x += dt v (plus the affine flow of a deforming or sheared
// box, whose lengths shear::box_drift has moved), wrap into the periodic box (Lees-Edwards
// shifted), and the largest displacement since the last neighbour build. Each thread moves the
// grains of its share (core/owned.hpp), adding each block's seconds to cost[b] (when not null).
void kick_drift(const Model& m, State& s, const Shares& shares, double* cost);
// The same drift without the kick (velocities given by a solve: the paste).
void drift(const Model& m, State& s);

// (particle_x, particle_r, particle_frozen, nbr_*, box, pair_*, every per-grain field when it
//  renumbers) => (nbr_start, pair_i, pair_j, pair_hist, pair_f, pair_touch, particle_disp,
//  nbr_strain, nbr_max_disp, nbr_valid, nbr_builds, every per-grain field)
// Rebuild the half Verlet list (cell list, pairs within r_i + r_j + skin) only when a grain
// moved more than skin/2 since the last build; tangential histories of surviving pairs are kept.
// Then re-select the contact candidates (contact_candidates.hpp) when they may have gone stale.
// Pre: nbr_start has N + 1 entries or the list is invalid. Post: has_pair_list; nbr_start[N] = P.
// Returns whether it renumbered the grains.
bool update_neighbors(const Model& m, State& s, DemWorkspace& w);
// Whether the state holds a valid pair list, one row per grain (what the pair forces need).
inline bool has_pair_list(const State& s) { return s.nbr_valid && static_cast<int64_t>(s.nbr_start.size()) == s.n + 1; }

// (dt, box, box_rate, shear_rate, particle_x, particle_v, particle_w, particle_r, inv_m,
//  nbr_start, pair_i, pair_j, pair_hist, pair_touch, pair_f) => (pair_f, pair_hist, pair_touch,
//  particle_f, particle_t [with friction], events.overlap)
// Normal law + tangential spring for every listed pair; the force on i stored per pair (in the
// steps whose end is seen), and the sum over all pairs of each grain in particle_f / particle_t
// (in the order of the pair schedule). With `then`, each block of grains then goes through it as
// soon as its sums are complete, and the largest displacements go to nbr_max_disp and
// nbr_step_disp (kick_and_next_drift).
void contact_forces(const Model& m, State& s, DemWorkspace& w, const GrainBlockPass* then = nullptr);

// (dt, particle_x, particle_v, particle_w, particle_r, inv_m, frozen, wall_hist) => (wall_f,
//  particle_t_wall, wall_hist, events.overlap)
void wall_forces(const Model& m, State& s);

// (dt, particle_f, particle_t [pair sums], every force source, inv_m, inv_i, frozen, shear_rate)
//  => (particle_f, particle_t, particle_v, particle_w, events.non_finite)
// Add the registered force sources (walls, then the other modules', in order) to the pair sums,
// then the second half kick, each thread on its share of the grains (as in kick_drift).
void kick(const Model& m, State& s, const ForceSources& sources, const Shares& shares, double* cost);
// (dt, particle_f, particle_t [pair sums], every force source, particle_x, particle_v, particle_w,
//  particle_disp, particle_id, inv_m, inv_i, frozen, box) => (particle_f, particle_t, particle_v,
//  particle_w, particle_x, particle_disp, nbr_max_disp, nbr_step_disp, events.non_finite_late,
//  events.non_finite)
// kick of the last step (its half step h_last), left to this one because nothing saw that step's
// end (State::boundary_seen), then kick_drift, block by block: the same operations on each grain,
// in the same order, as the two passes (the same bits), in one pass and without a join. A fixed
// box only.
void late_kick_drift(const Model& m, State& s, const ForceSources& sources, double h_last, const Shares& shares,
                     double* cost);
// The grain pass that a step whose end nothing sees runs inside its pair loop, block by block as
// each block's sums are complete (contact_forces): kick, then the next step's kick_drift (its dt
// is this one's: a fixed step), with no force source but the pairs and a fixed box. pass(b, e)
// returns the largest squared displacements of the grains [b, e) (as kick_drift's). A non-finite
// motion after the kick is this step's (events.non_finite; the block is not moved); a non-finite
// position after the drift is the next step's: it goes to drift_events, which the next step's
// kick_drift raises.
GrainBlockPass kick_and_next_drift(const Model& m, State& s, EventSlot* drift_events);
// (particle_f, particle_t, every force source) => (particle_f, particle_t)
// The same sum without the kick: the forces of the first state.
void sum_forces(const Model& m, State& s, const ForceSources& sources);

// (pair_hist, wall_hist) => (pair_hist, wall_hist)
// The first state's force evaluation stretches the springs by a step it does not take: the
// springs are kept before it and put back after it. A new state's are then zero (no tangential
// history exists before the first step), and a packing made by another run (prepare.compress)
// keeps the springs that hold it.
void keep_springs(const State& s, DemWorkspace& w);
void restore_springs(State& s, const DemWorkspace& w);

// (step, t, dt, particle_v, particle_w, inv_m, inv_i, frozen) => (events.runaway)
// Every limits.check_every steps (at the step that makes the count a multiple of it): the
// kinetic energy against limits.energy_factor times what the scene can have supplied by the end
// of the step (limits.energy_supply).
void energy_check(const Model& m, State& s);

// Kinetic energy of the free grains, translation + rotation, and its rotational part, summed in
// grain order (the energy check and the `ke` observable).
struct KineticEnergy {
  double total = 0, rot = 0;
};
KineticEnergy kinetic_energy(const State& s);
// Elastic energy stored in the contacts, normal and tangential springs, grain-grain and
// grain-wall (contact_laws.hpp); with k_t = kt_over_kn k_n(h), exact for the linear laws, for
// Hertz the spring's energy at its current stiffness.
double contact_energy(const Model& m, const State& s);

}  // namespace silt::dem
