// The DEM's stages. In a step:
//
//   choose_dt -> kick_drift -> update_neighbors -> contact_forces --> kick -> energy_check
//                                      \------> wall_forces ---/
//
// and for the forces of the first state: update_neighbors -> keep_springs -> (contact_forces |
// wall_forces) -> sum_forces, then restore_springs. The forces of a state made under other
// parameters (dem/forces_under.hpp), made again before its step: the same without the neighbour
// update, when forces_stale finds them so.
#include <cmath>
#include <memory>

#include "dem/contact_candidates.hpp"
#include "dem/contact_setup.hpp"
#include "dem/escaped.hpp"
#include "dem/forces_under.hpp"
#include "dem/stages.hpp"
#include "graph/adders.hpp"
#include "shear/collisions.hpp"
#include "silt/module.hpp"
#include "silt/observables.hpp"
#include "silt/text.hpp"

namespace silt::graph {
namespace {

// What each stage reads and writes (their contracts in dem/stages.hpp).
const Access kGrainConst = {fid::particle_r, fid::particle_inv_m, fid::particle_inv_i, fid::particle_frozen};

Access with(Access a, const Access& b) { return join(std::move(a), b); }

Access kick_drift_reads(const Model& m) {
  Access r = with({fid::dt, fid::box, fid::particle_v, fid::particle_w, fid::particle_f, fid::particle_t,
                   fid::particle_x, fid::particle_disp},
                  kGrainConst);
  if (m.deforming_box()) r = with(r, {fid::box_stretch, fid::shear_rate});
  return r;
}

Access neighbor_reads() {
  return with(grain_fields(),
              {fid::box, fid::nbr_valid, fid::nbr_max_disp, fid::nbr_step_disp, fid::nbr_strain, fid::nbr_builds,
               fid::nbr_start, fid::pair_i, fid::pair_j, fid::pair_hist, fid::pair_f, fid::pair_touch});
}
Access neighbor_writes() {
  return with(grain_fields(), {fid::nbr_start, fid::pair_i, fid::pair_j, fid::pair_hist, fid::pair_f, fid::pair_touch,
                               fid::nbr_strain, fid::nbr_max_disp, fid::nbr_valid, fid::nbr_builds});
}

Access contact_reads(const Model& m) {
  Access r = with({fid::dt, fid::box, fid::particle_x, fid::particle_v, fid::particle_w, fid::nbr_valid, fid::nbr_start,
                   fid::pair_i, fid::pair_j, fid::pair_touch, fid::pair_f},
                  kGrainConst);
  // Friction is steerable: the springs and torques are declared whether or not it is on now
  // (without it they are left as they were: read).
  r = with(r, {fid::pair_hist, fid::particle_t});
  if (m.deforming_box()) r = with(r, {fid::box_rate, fid::shear_rate});
  if (!m.pair_contact.empty()) r = with(r, {fid::particle_group});  // the materials of the pair
  return r;
}
Access contact_writes() {
  Access w = {fid::pair_f, fid::pair_touch, fid::particle_f};
  w = with(w, {fid::pair_hist, fid::particle_t});
  return w;
}

const Access kWallReads = with(
    {fid::dt, fid::particle_x, fid::particle_v, fid::particle_w, fid::wall_hist, fid::particle_group}, kGrainConst);
const Access kWallWrites = {fid::wall_f, fid::particle_t_wall, fid::wall_hist};

Access kick_reads(const Model& m) {
  Access r = with({fid::dt, fid::particle_f, fid::particle_v, fid::particle_w}, kGrainConst);
  r = with(r, {fid::particle_t});
  if (m.shear.on) r = with(r, {fid::shear_rate});
  return r;
}
const Access kKickWrites = {fid::particle_f, fid::particle_t, fid::particle_v, fid::particle_w};

// The contacts grain i (an index) holds: with grains (the listed pairs that touch) and walls.
int64_t contacts_of(const Model& m, const State& s, int64_t i) {
  int64_t z = 0;
  for (int64_t k = 0; k < s.n_pairs(); ++k)
    if (s.pair_touch[k] && (s.pair_i[k] == i || s.pair_j[k] == i)) ++z;
  for (int w = 0; w < s.n_walls; ++w)
    if (m.walls[w].gap(m.dim, &s.particle_x[m.dim * i], s.particle_r[i]) < 0) ++z;
  return z;
}

void diagnose_dem(GraphBuilder& b) {
  // A grain id in a step's kick or drift: a time step too large for the contacts it meets.
  // The key that sets the step: run.dt, or the module's that chooses it (a paste's).
  auto step_advice = [](const Model& m) {
    return "reduce " + m.dt_key + (m.dt_key == "run.dt" ? " (or run.dt_over_tc)" : "");
  };
  auto non_finite = [step_advice](const Model& m, const State& s, int64_t id, StepFailure& f) {
    f.stage = "kick";
    f.particle = id;
    f.parameter = m.dt_key;
    f.message = "grain " + std::to_string(id) + " has a non-finite velocity or position; the time step " +
                format_number(s.dt, 4) + m.unit("s") + " is too large for the contacts it meets: " + step_advice(m);
  };
  b.diagnose(event::kNonFinite, [non_finite](const Model& m, const State& s, const EventSlot& e, StepFailure& f) {
    non_finite(m, s, s.particle_id[e.first()], f);
  });
  b.diagnose(event::kNonFiniteLate, [non_finite](const Model& m, const State& s, const EventSlot& e, StepFailure& f) {
    // The second half kick of the step before, left to this one (dem::late_kick_drift): that
    // step failed. The index is the grain's id.
    non_finite(m, s, e.first(), f);
    f.step = s.step - 1;
  });
  b.diagnose(event::kOverlap, [step_advice](const Model& m, const State& s, const EventSlot& e, StepFailure& f) {
    const int64_t i = e.first(), id = s.particle_id[i];
    // The wall the grain overlaps beyond the limit, if one does, and its overlap: the key of that
    // contact's law is the one to name (a wall of young_modulus 1e-300 was reported against
    // contact.young_modulus, as "a neighbour or a wall").
    int wall = -1;
    double wall_overlap = 0;
    for (int w = 0; w < s.n_walls && wall < 0; ++w) {
      wall_overlap = -m.walls[w].gap(m.dim, &s.particle_x[m.dim * i], s.particle_r[i]) / s.particle_r[i];
      if (wall_overlap > m.limits.max_overlap) wall = w;
    }
    const std::string what =
        "grain " + std::to_string(id) +
        (wall >= 0 ? " overlaps walls[" + std::to_string(wall) + "] by " + format_number(100 * wall_overlap, 4) +
                         "% of its radius"
                   : " overlaps a neighbour by " + format_number(100 * e.value(), 4) + "% of the smaller radius") +
        ", beyond limits.max_overlap = " + format_number(m.limits.max_overlap, 4);
    f.stage = wall >= 0 ? "wall_forces" : "contact_forces";
    f.particle = id;
    if (m.velocities_solved) {
      // The step moved the grains with solved velocities: the DEM's inertial limit is not theirs.
      // (An adaptive paste's step is bounded by the drift: the bound is the key to lower.)
      // Unless the contacts are soft for the pressure: they deflect by about a / kappa (Peyneau eq.
      // 1.32), 2 / kappa of a radius at the mean force. Above a fifth of limits.max_overlap (kappa
      // below 50 by default), a force chain's contacts reach it whatever the step (a sheared paste
      // given box.pressure = 1e3 on k_n = 1e4, kappa = 10, was told to lower drift_max, which failed
      // the same way).
      const double kappa = m.box_control.on ? stiffness_number(m, m.box_control.pressure) : 0.0;
      if (kappa > 0 && 2 / kappa > m.limits.max_overlap / 5) {
        f.parameter = m.kappa_softest_key;
        f.message = what +
                    ": the contacts are too soft for box.pressure = " + format_number(m.box_control.pressure, 4) +
                    m.unit("Pa") + " (stiffness number kappa = " + format_number(kappa, 3) +
                    ": at the mean force they deflect by about 2 / kappa = " + format_number(200 / kappa, 3) +
                    "% of a radius); " + (m.contact.law == NormalLaw::kSpringDashpot ? "shorten " : "raise ") +
                    f.parameter + " or lower box.pressure (packings are run at kappa 1e3 and more)";
      } else {
        f.parameter = m.drift_key.empty() ? m.dt_key : m.drift_key;
        f.message = what + ": the step of " + format_number(s.dt, 4) + m.unit("s") +
                    " moved the grains into each other; lower " + f.parameter;
      }
    } else if (s.dt > m.dt_stable) {
      f.parameter = m.dt_key;
      f.message = what + ": the time step " + format_number(s.dt, 4) + m.unit("s") + " exceeds the stability limit " +
                  format_number(m.dt_stable, 4) + m.unit("s") + "; " + step_advice(m);
    } else if (s.dt > 0.9 * m.dt_stable) {
      // Near the limit the integration makes a contact softer than it is, and a grain held by z
      // contacts is stable below about limit / sqrt(z): a step of 0.996 of one contact's limit
      // failed a settling packing, which was told its contacts were too soft.
      f.parameter = m.dt_key;
      f.message = what + ": the time step " + format_number(s.dt, 4) + m.unit("s") + " is " +
                  format_number(s.dt / m.dt_stable, 3) + " of one contact's stability limit " +
                  format_number(m.dt_stable, 4) + m.unit("s") +
                  ", where the integration softens the contacts (a grain held by z of them is stable below about "
                  "limit/sqrt(z)); " +
                  step_advice(m);
    } else if (const int64_t z = contacts_of(m, s, i);
               z > 1 && s.dt > m.dt_stable / std::sqrt(static_cast<double>(z))) {
      // Held by z contacts the grain is stable below about limit / sqrt(z) (a hexagonal lattice at
      // dt_over_tc = 0.4, 0.63 of one contact's limit, was told its contacts were too soft, and
      // stiffer ones, with the step in units of their time, failed the same way).
      f.parameter = m.dt_key;
      f.message = what + ": the time step " + format_number(s.dt, 4) + m.unit("s") + " is " +
                  format_number(s.dt / m.dt_stable, 3) + " of one contact's stability limit " +
                  format_number(m.dt_stable, 4) + m.unit("s") +
                  ", above limit/sqrt(z) = " + format_number(m.dt_stable / std::sqrt(static_cast<double>(z)), 4) +
                  m.unit("s") + " for its z = " + std::to_string(z) + " contacts; " + step_advice(m);
    } else {
      const int groups = static_cast<int>(m.materials.size()), g = s.particle_group[i];
      f.parameter =
          wall >= 0 && groups > 0
              ? dem::stiffness_key(m.desc, m.wall_contact[wall * groups + g].law,
                                   {"walls[" + std::to_string(wall) + "].", "grains[" + std::to_string(g) + "]."})
          : groups > 0 && !m.pair_contact.empty()
              ? dem::stiffness_key(m.desc, m.contact.law, {"grains[" + std::to_string(g) + "]."})
              : dem::stiffness_key(m.desc, m.contact.law);
      // A shorter contact time is a stiffer spring (k ~ 1 / t_c^2); a larger modulus or k_n is.
      const bool by_time = m.contact.law == NormalLaw::kSpringDashpot;
      // The collisions of an imposed shear (shear.inertial_number = 10 was told only to stiffen).
      if (const std::string sheared = wall < 0 ? shear::shear_overlap_advice(m, s, f.parameter) : ""; !sheared.empty())
        f.message = what + ": " + sheared;
      else
        f.message = what + ": the contacts are too soft for the loads or the impacts; " +
                    (by_time ? "decrease " : "increase ") + f.parameter + " (stiffer contacts) or reduce the loads";
    }
  });
  b.diagnose(event::kRunaway, [step_advice](const Model& m, const State& s, const EventSlot& e, StepFailure& f) {
    f.stage = "energy_check";
    // A grain falling out through an open face gains the energy without bound: not the step's
    // fault (a smaller one failed at the same time).
    if (const std::string out = dem::escaped_grain(m, s); !out.empty()) {
      f.parameter = "walls";
      f.message = "kinetic energy " + format_number(e.value(), 4) + m.unit("J") + " beyond the energy the scene can " +
                  "supply: " + out + "; " + dem::kEscapeAdvice;
      return;
    }
    f.parameter = m.dt_key;
    f.message = "kinetic energy " + format_number(e.value(), 4) + m.unit("J") + " exceeds " +
                format_number(m.limits.energy_factor, 4) + " times the energy the scene can supply (" +
                format_number(m.limits.energy_supply(s.t + s.dt), 4) + m.unit("J") +
                "): the integration is unstable; " + step_advice(m);
  });
}

// Whether the DEM's are the only stages of the step besides the core's: the shear's box stages
// read the velocities and the forces at the end of every step, a drag or a fluid computes forces
// from the velocities, a module added at run time may read anything.
bool dem_alone(const Model& m) {
  for (const Module& mod : modules()) {
    const std::string& name = mod.spec->name;
    if (name != "core" && name != "dem" && name != "render" && m.module_on(name)) return false;
  }
  return true;
}

// The forces of the first state (setup), or of a state given or steered under other parameters
// than those it holds them under (refresh, `gated`: only when forces_stale finds them so), made at
// its positions and velocities: the springs kept, stretched by a step they do not take and put
// back; the other modules' forces, a drag's, join the sum (the list is the state's); the
// parameters recorded. `first` is the stage before: the setup's neighbour list, the refresh's
// forces_stale.
void add_first_forces(GraphBuilder& b, int first, bool gated) {
  const Model& m = b.model();
  auto& w = b.workspaces().get<dem::DemWorkspace>();
  auto forces = b.forces();
  const bool walls = !m.walls.empty();
  // Whether the forces are made (always in the setup).
  auto on = [&w, gated] { return !gated || w.refresh; };
  // A gated stage may leave what it writes as it was: it reads it too.
  auto reads = [gated](const Access& r, const Access& written) { return gated ? with(r, written) : r; };
  const Access springs = {fid::pair_hist, fid::wall_hist};
  if (gated) {
    // A state given or restored comes without contact candidates (its workspace invalidated):
    // chosen here, before the springs are kept, as update_neighbors chooses them in a step. The
    // choice clears a pair left out that still holds a spring (dem/contact_candidates.hpp), and
    // its workspace carries them to the next call, so the access check runs it once.
    const Access pair_state = {fid::pair_touch, fid::pair_f, fid::pair_hist};
    const int choose = b.add(
        "select_candidates",
        [&w, on](const Model& mm, State& s) {
          if (on() && !w.candidates_valid) dem::select_candidates(mm, s, w);
        },
        with({fid::box, fid::particle_x, fid::particle_r, fid::nbr_valid, fid::nbr_start, fid::pair_i, fid::pair_j,
              fid::nbr_strain},
             pair_state),
        pair_state);
    b.after(choose, first, "only when the forces are stale");
    b.carries_workspace(choose);
    first = choose;
  }
  const int keep = b.add("keep_springs",
                         [&w, on](const Model&, State& s) {
                           if (on()) dem::keep_springs(s, w);
                         },
                         springs, {});
  b.after(keep, first, gated ? "the candidates' springs" : "the springs of the (possibly rebuilt) pair list");
  const int pairs = b.add(
      "contact_forces",
      [&w, on](const Model& mm, State& s) {
        if (on()) dem::contact_forces(mm, s, w);
      },
      reads(contact_reads(m), contact_writes()), contact_writes());
  if (!gated) b.after(pairs, first, "iterates the (possibly rebuilt) pair list");
  b.after(pairs, keep, "stretches the springs kept");
  int wf = -1;
  if (walls) {
    wf = b.add(
        "wall_forces",
        [on](const Model& mm, State& s) {
          if (on()) dem::wall_forces(mm, s);
        },
        reads(kWallReads, kWallWrites), kWallWrites);
    if (!gated) b.after(wf, first, "a rebuild may renumber the grains (cell order)");
    b.after(wf, keep, "stretches the springs kept");
    b.add_force({fid::wall_f, fid::particle_t_wall}, wf);
  }
  const int sum = b.add("sum_forces",
                        [forces, on](const Model& mm, State& s) {
                          if (on()) dem::sum_forces(mm, s, *forces);
                        },
                        {fid::particle_f, fid::particle_t}, {fid::particle_f, fid::particle_t});
  b.after(sum, pairs, "adds the pair forces made");
  b.sums_forces(sum);
  const int restore = b.add(
      "restore_springs",
      [&w, on](const Model&, State& s) {
        if (on()) dem::restore_springs(s, w);
      },
      reads({}, springs), springs);
  b.after(restore, pairs, "puts back the springs the evaluation stretched");
  if (walls) b.after(restore, wf, "puts back the springs the evaluation stretched");
  const FieldId under = dem::forces_under_field();
  const int record = b.add("record_forces_under",
                           [on](const Model& mm, State& s) {
                             if (on()) dem::record_forces_under(mm, s);
                           },
                           reads({}, {under}), {under});
  if (gated) b.after(record, first, "records the parameters found stale");
  b.light(record);
}

void add_refresh_stages(GraphBuilder& b) {
  auto& w = b.workspaces().get<dem::DemWorkspace>();
  // Forces need a pair list: a state without a valid one (grains frozen, a checkpoint that says so)
  // keeps its forces until the next step's, which builds the list first (its first half kick then
  // uses the forces of the parameters the state held).
  const int stale =
      b.add("forces_stale",
            [&w](const Model& mm, State& s) { w.refresh = dem::has_pair_list(s) && dem::forces_under_other(mm, s); },
            {dem::forces_under_field(), fid::nbr_valid, fid::nbr_start}, {});
  b.light(stale);
  add_first_forces(b, stale, true);
  diagnose_dem(b);
}

}  // namespace

void add_dem_stages(GraphBuilder& b) {
  if (b.phase() == Phase::kResolve || b.phase() == Phase::kRefresh) return add_refresh_stages(b);
  const Model& m = b.model();
  auto& w = b.workspaces().get<dem::DemWorkspace>();
  const bool walls = !m.walls.empty();
  auto forces = b.forces();
  Workspaces& all = b.workspaces();
  // A step whose end nothing sees leaves its second half kick to the next step's kick_drift
  // (dem::late_kick_drift): one pass over the grains and one join fewer. Only the DEM's own
  // stages may run in between (dem_alone).
  const bool fold = b.phase() == Phase::kStep && !m.velocities_solved && !m.adaptive_dt && dem_alone(m);
  // Without walls the pairs are the only force: such a step's pair loop kicks each block of grains
  // and runs the next step's kick_drift on it as soon as its sums are complete
  // (dem::kick_and_next_drift), by the thread that holds it. The kick and the drift then need no
  // pass nor join of their own, and a block's grains are moved while they are in its cache.
  const bool early = fold && !walls;
  const Access drift_writes = {fid::particle_v,    fid::particle_w,   fid::particle_x,
                               fid::particle_disp, fid::nbr_max_disp, fid::nbr_step_disp};
  const int nbr = b.add(
      "update_neighbors",
      [&w, &all](const Model& mm, State& s) {
        if (dem::update_neighbors(mm, s, w)) all.renumbered(&w);
      },
      neighbor_reads(), neighbor_writes());
  // Its workspace carries the travel since the contact candidates were chosen from one call to
  // the next (dem::update_candidates adds the step's largest displacement to it): a second call
  // on the same state may choose them again where the first did not, so the access check runs it
  // once (its writes checked, not its reads). Found by the checkpoint fuzzer on a restored state
  // whose candidates then changed the pairs' springs.
  b.carries_workspace(nbr);
  if (b.phase() == Phase::kSetup) return add_first_forces(b, nbr, false);
  const int pairs = b.add(
      "contact_forces",
      [&w, early](const Model& mm, State& s) {
        // One thread has no join to save, and runs the two passes a little faster (the kick is
        // then left to the next kick_drift).
        if (!early || s.boundary_seen || owner_count() < 2) return dem::contact_forces(mm, s, w);
        w.drift_step = s.step;
        w.drift_events.clear();
        const dem::GrainBlockPass then = dem::kick_and_next_drift(mm, s, &w.drift_events);
        dem::contact_forces(mm, s, w, &then);
      },
      // The drift's scalars are read too: a step that is seen leaves them as they were.
      early ? with(contact_reads(m),
                   with(kick_drift_reads(m), with(kick_reads(m), {fid::step, fid::nbr_max_disp, fid::nbr_step_disp})))
            : contact_reads(m),
      early ? with(contact_writes(), with(drift_writes, kKickWrites)) : contact_writes());
  // depends on: the list, and the grains' numbering, that update_neighbors leaves.
  b.after(pairs, nbr, "iterates the (possibly rebuilt) pair list");
  if (walls) {
    const int wf = b.add("wall_forces", &dem::wall_forces, kWallReads, kWallWrites);
    // Runs concurrently with contact_forces; not with update_neighbors, which may renumber grains.
    b.after(wf, nbr, "a rebuild may renumber the grains (cell order)");
    b.add_force({fid::wall_f, fid::particle_t_wall}, wf);
  }
  if (m.velocities_solved) {
    // Velocities from a solve (the paste): the grains drift with them; no kick, no energy check.
    const int drift = b.add("drift", &dem::drift, kick_drift_reads(m), drift_writes);
    b.after(drift, b.find("choose_dt"), "moves the grains by this step's dt");
    b.after(nbr, drift, "rebuild decision needs the drifted positions");
    diagnose_dem(b);
    return;
  }
  Access drift_reads = kick_drift_reads(m);
  Access late_writes = drift_writes;
  if (fold) {
    // A step after one that moved the grains in its pair loop leaves the drift's scalars as they
    // were: read.
    drift_reads =
        with(drift_reads, with(kick_reads(m), {fid::particle_id, fid::step, fid::nbr_max_disp, fid::nbr_step_disp}));
    late_writes = with(late_writes, kKickWrites);
  }
  const int drift = b.add(
      "kick_drift",
      [&w, forces](const Model& mm, State& s) {
        if (w.drift_step == s.step - 1) {  // done by the last step's pair loop: raise what it met
          if (w.drift_events.raised()) s.events[event::kNonFinite].raise(w.drift_events.first(), 0);
          return;
        }
        double* cost = w.block_cost[dem::DemWorkspace::kGrainPasses].data();
        if (w.kick_step != s.step - 1) return dem::kick_drift(mm, s, w.shares, cost);
        dem::late_kick_drift(mm, s, *forces, w.kick_h, w.shares, cost);
      },
      drift_reads, late_writes);
  b.after(drift, b.find("choose_dt"), "moves the grains by this step's dt");
  // depends on: the displacement since the last build, known after the drift.
  b.after(nbr, drift, "rebuild decision needs the drifted positions");
  const int kick = b.add(
      "kick",
      [forces, &w, fold](const Model& mm, State& s) {
        if (w.drift_step == s.step) return;  // done in the pair loop
        if (fold && !s.boundary_seen) {
          w.kick_step = s.step;
          w.kick_h = 0.5 * s.dt;
          return;
        }
        dem::kick(mm, s, *forces, w.shares, w.block_cost[dem::DemWorkspace::kGrainPasses].data());
      },
      fold ? with(kick_reads(m), {fid::step}) : kick_reads(m), kKickWrites);
  b.after(kick, pairs, "kicks with the pair forces of this step");
  b.sums_forces(kick);
  if (fold) b.sums_last_forces(drift);
  const int energy = b.add("energy_check", &dem::energy_check,
                           with({fid::step, fid::t, fid::dt, fid::particle_v, fid::particle_w}, kGrainConst), {});
  b.after(energy, kick, "the energy of the full-step velocities");
  b.light(energy);  // a pass over the grains once in limits.check_every steps
  diagnose_dem(b);
}

}  // namespace silt::graph
