// The paste's stages (engine/graph/paste_stages.cpp puts them in the step):
//
//   choose_dt -> paste_dt -> lubrication_resolve -> drift -> update_neighbors -> contact_forces
//   -> lubrication_solve
//
// paste_dt sets the step's dt from the adaptive step (sec. 2.2.4); lubrication_resolve solves the
// velocities again when they were solved under other parameters (steered, or a checkpoint
// restored under other ones: a viscosity, a pressure, a rate, the roughness); the DEM's drift moves the
// grains by dt V with the velocities of the last solve (explicit Euler, eq. 2.19 of Peyneau
// 2009: contact forces and Xi at the start of the step); lubrication_solve finds the
// connections, assembles Xi, solves for every grain's velocity and angular velocity (and the
// strain rates of the controlled box lengths) at once, stores the lubrication force of every
// connection and chooses the next step's dt.
#pragma once

#include <limits>

#include "core/workspace.hpp"
#include "paste/params.hpp"
#include "paste/system.hpp"
#include "silt/events.hpp"
#include "silt/linalg.hpp"
#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::paste {

// The paste's own fields (registered by its module spec).
struct PasteFields {
  FieldId pair_f_lub, dt, solver, change, factor, alone, coarse_order, dt_scale, solved_under, pair_f_implicit,
      forces_under;
};
PasteFields paste_fields();

// paste_solver, a free-length field of kSolverStats entries:
enum SolverStat {
  kLastIterations,    // CG iterations of the last solve (0 for a direct solve)
  kLastResidual,      // its relative residual |b - Xi V| / |b|
  kSolves,            // solves so far
  kIterationsTotal,   // their iterations
  kIterationsMax,     // the most one took
  kRefactorizations,  // Cholesky factorisations so far (a direct solve: one each)
  kFactorAge,         // solves the held factor has served, -1 when none is held
  kLastStatus,        // linalg::SolveStatus of the last solve
  kConnections,       // connections of the last solve
  kCoarseColumns,     // columns of the factor's coarse correction in the last solve
  kStressError,       // the last solve's estimated error of the grains' stress, relative to it
  kStressNotice,      // bits: 1 that error above lubrication.stress_tolerance now, 4 as the run was last
                      // told, 2 when the two differ (said after the step: stress_notice)
  kSolverStats
};

// kStressError where none was estimated (the check off, a direct solve): a state's values are
// finite, so that a checkpoint of it restores; read as nan (stress_error_of).
inline constexpr double kNoStressError = -1;
inline double stress_error_of(double stored) { return stored < 0 ? std::numeric_limits<double>::quiet_NaN() : stored; }

// kStressNotice's bits (0 for a value that is not a whole number from 0 to 7: a checkpoint edited).
inline int stress_notice_bits(double v) {
  return v >= 0 && v <= 7 && v == static_cast<int>(v) ? static_cast<int>(v) : 0;
}

struct PasteWorkspace final : Workspace {
  linalg::SpdSolver solver;
  ResistanceSystem system;
  Links links;
  std::vector<int32_t> component;
  std::vector<double> scratch;  // the adaptive step's new Xi diagonal and right-hand side
  linalg::Vector error;         // the solve's error estimate (stress_tolerance)
  bool fresh = true;            // made, or invalidated: the factor is rebuilt from the state's copy
  uint64_t factor_hash = 0;     // of the state's copy of the matrix the held factor was made from
  void invalidate() override {
    fresh = true;
    factor_hash = 0;
    system.forget();
    solver.forget_factor();
  }
  size_t bytes() const override {
    return system.bytes() + static_cast<size_t>(solver.factor().factor_bytes() + solver.coarse().bytes()) +
           links.c.size() * (sizeof(Connection) + sizeof(int32_t)) +
           (scratch.capacity() + static_cast<size_t>(error.size())) * sizeof(double);
  }
};

// The event a failed solve raises: index the linalg::SolveStatus, value the residual (or, when a
// factorisation found Xi not positive definite, the unknown where it did).
EventId solve_event();
// The same, raised by the solve again under parameters changed between steps (lubrication_resolve).
EventId resolve_event();
// The event of an adaptive step below lubrication.dt_min: value the step wanted, index what wanted it.
EventId step_event();
enum StepLimit : int64_t { kChangeLimit = 0, kDriftLimit = 1 };  // the change of Xi or the forces; the drift
// The largest |V_i| / r_i over the grains, V relative to the affine flow: a step of dt moves no
// grain by more than dt times this of its radius (lubrication.drift_max bounds it).
double fastest_rate(const State& s);
// The event of an inertial solve whose lightest grain's m / dt is below kMassResolution times Xi's
// largest translational resistance: index the grain, value the ratio.
EventId mass_event();
// Below this ratio (a few times the double's epsilon) the inertial matrix M / dt + Xi cannot
// resolve the grains' common translations, which only the masses resist: measured on a 56-disk
// paste, 2.5e-17 (grains of density 1e-16) changed the run and 4e-18 made the factor fail.
constexpr double kMassResolution = 1e-14;

// (dt, paste_dt, paste_dt_scale) => (dt): the adaptive step; when the model's time scale fell below
// the one it was chosen under (steered), the step cut in proportion.
void paste_dt(const Model& m, State& s);

// When a solve runs: at the end of a step (the velocities of the next one, which also chooses its
// step), for the first state, or again at the start of a step whose velocities were solved under
// other parameters (at the state's time and this step's dt; the adaptive step left as it is).
enum class SolveAt { kStep, kFirst, kAgain };

// (t, dt, particle_x, particle_r, particle_v, particle_w, particle_f, particle_t, particle_inv_m,
//  particle_inv_i, particle_id, nbr_start, pair_j, pair_f, pair_hist, particle_group, box,
//  box_rate, shear_rate, paste_*) =>
// (particle_v, particle_w, box_rate, pair_f_lub, paste_dt, paste_solver, paste_change,
//  paste_factor, paste_alone, paste_coarse_order, paste_dt_scale, paste_solved_under,
//  paste_forces_under)
void lubrication_solve(const Model& m, State& s, PasteWorkspace& w, SolveAt at);

// The same access, and shear_rate written (an imposed rate changed: the model's, which box_drift
// sets later in the step): lubrication_solve(kAgain) when the quasi-static velocities in the state were
// solved under parameters other than the model's (paste_solved_under), else nothing. The inertial
// stepper's velocities are the grains' own and carry over a change.
// at_boundary: the solve of a state given (Phase::kResolve), whose notes are said at once; else
// the first stage of a step, whose solve after it says them.
void lubrication_resolve(const Model& m, State& s, PasteWorkspace& w, bool at_boundary = false);
// Whether the state's quasi-static velocities were solved under other parameters than the model's,
// or with contact forces made since under other parameters (dem/forces_under.hpp): lubrication_resolve
// solves them again; a state restored so is solved again before its first sample (ModuleSpec::stale).
bool solved_under_other(const Model& m, const State& s);

// The stepper's name, for reports.
const char* stepper_name(Stepper s);

// What the run says when the grains with no lubricated connection change (paste_alone): their
// ids, or that every grain is connected again; "" when the last solve left the set as it was.
std::string alone_notice(const State& s);

}  // namespace silt::paste
