// The fluid's step (Izard 2014 sec. 2.2): incompressible Navier-Stokes on the staggered grid,
//   du/dt + div(u u) = -grad p / rho + nu Lap u + f,   div u = 0,
// advanced by the low-storage third-order Runge-Kutta scheme of Wray (1990) (as in Spalart,
// Moser & Rogers 1991 and CaNS) with an incremental pressure correction at each of its three
// substeps (van Kan 1986; Brown, Cortez & Minion 2001), p the pressure / rho so far:
//   u* = u^k + dt (gamma_k N(u^k) + zeta_k N(u^(k-1))) - alpha_k dt grad p
//        + alpha_k dt nu Lap (u^k + u*) / 2                                   (Crank-Nicolson)
//      (or + alpha_k dt nu Lap u*, backward Euler; or + alpha_k dt nu Lap u^k, explicit),
//   Lap phi = div u* / (alpha_k dt),   u^(k+1) = u* - alpha_k dt grad phi,   p += phi,
// gamma = (8/15, 5/12, 3/4), zeta = (0, -17/60, -5/12), alpha = gamma + zeta = (8/15, 2/15, 1/3).
// The increment phi is O(dt): the splitting error of the projection is O(dt^2), where a
// projection of the whole pressure (phi = p) leaves O(dt) at the walls.
// N is the advection in divergence form (energy-conserving) plus the body force, and the
// viscous term with the explicit scheme.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/large_array.hpp"
#include "core/workspace.hpp"
#include "fluid/fast_solver.hpp"
#include "fluid/layout.hpp"
#include "fluid/params.hpp"
#include "silt/events.hpp"
#include "silt/linalg.hpp"
#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::fluid {

class PoissonSolver;

// Ids of the fluid's State fields.
struct FluidFields {
  std::array<FieldId, 3> u;  // fluid_u, fluid_v, fluid_w: velocity components on the faces [m/s]
  FieldId p;                 // fluid_p: pressure at the cell centres [Pa]
  FieldId stat;              // fluid_stat: the step's numbers (FluidStat)
};
FluidFields fluid_fields();

// Entries of the fluid_stat field.
enum FluidStat : int {
  kDtNext,    // the next adaptive step [s]
  kDivMax,    // largest |div u| after the last projection [1/s]
  kCfl,       // dt sum_a max |u_a| / h_a of the last step
  kIters,     // iterations of the last pressure solve (0 for the transforms)
  kResidual,  // its relative residual
  kSolves,    // pressure solves so far
  kItersSum,  // their iterations
  kItersMax,
  kDriveGradient,  // the mean pressure gradient that holds the imposed flow rate [Pa/m]
  kCellSteps,      // cell-steps advanced so far
  kRate,           // sum_a max |u_a| / h_a of the state [1/s] (the CFL number is dt times it)
  // max |u^(n+1) - u^n| / (dt max(max |u^(n+1)|, max |u^n|)) over the faces in the last step
  // [1/s]: the relative change of the velocity per unit time, which run.stop_when_steady compares
  // with run.steady_tol (times L / U). Last, so that a checkpoint written before it existed still
  // reads (kStatCount - 1 entries).
  kChangeRate,
  kStatCount
};

// Events: a CFL or viscous number beyond the scheme's stability, a non-finite velocity, a
// pressure solve that did not converge.
EventId cfl_event();
EventId nonfinite_event();
EventId solve_event();

struct FluidWorkspace final : Workspace {
  bool ready = false;
  Layout L;
  std::array<LargeArray<double>, 3> u, u_star, n_prev, bc_lap;  // padded
  std::array<double, 18> bc_velocities{};                       // the face velocities bc_lap was made for
  bool bc_lap_ready = false;
  LargeArray<double> phi;       // padded: the pressure increment of the substep
  LargeArray<double> p_kin;     // padded: the pressure / rho so far (incremental projection)
  LargeArray<double> cells;     // one value per cell (solver)
  LargeArray<double> unknowns;  // one component's unknowns (Helmholtz)
  // Flow-rate drive with an implicit viscous term: (1 - beta Lap)^-1 1 of each substep, its mean, and
  // the beta it was solved for (made again only when beta changes: a new step size or viscosity).
  std::array<std::vector<double>, 3> drive_shape;
  std::array<double, 3> drive_beta{}, drive_mean{};
  std::unique_ptr<FastSolver> poisson;
  std::array<std::unique_ptr<FastSolver>, 3> helmholtz;
  // The step under way: its dt, the substep (0 .. 2), the flow-rate drive's sum, and whether an
  // event stopped it.
  double dt = 0, drive = 0;
  int substep = 0;
  bool failed = false;
  std::shared_ptr<PoissonSolver> multigrid;  // fluid/multigrid.hpp, for projection = multigrid_cg
  linalg::Vector mg_x;                       // its solution
  // A state replaced (a restore, the replay of a failed step): the arrays it held are not that
  // state's (a failed step's NaN stayed in n_prev, which the first substep multiplies by 0): made
  // anew. Nothing held depends on the grains' numbering.
  void invalidate() override { ready = false; }
  void renumbered() override {}
  size_t bytes() const override;
};

// The stages of a step of dt (graph/fluid_stages.cpp): fluid_load, then three times fluid_momentum,
// fluid_viscous (an implicit viscous term only), fluid_pressure and fluid_project, then fluid_store. They
// share the workspace's padded arrays; the State is read by fluid_load and written by
// fluid_store. After an event (a CFL number beyond the limit, a solve that failed) the others
// return at once.
//   fluid_load      (fluid_u, fluid_v, fluid_w, fluid_p, fluid_stat, dt) => (fluid_stat, workspace)
//   fluid_momentum  u* = u + dt (gamma N + zeta N') [+ beta (Lap u + Lap_bc)]
//   fluid_viscous   (1/beta - Lap) u* = rhs / beta
//   fluid_pressure  Lap phi = div u* / (alpha dt)           => (fluid_stat: the solve's numbers)
//   fluid_project   u = u* - alpha dt grad phi (and the flow-rate drive)
//   fluid_store     workspace => (fluid_u, fluid_v, fluid_w, fluid_p, fluid_stat); raises nonfinite_event
void fluid_load(const Model& m, State& s, FluidWorkspace& w);
void fluid_momentum(const Model& m, State& s, FluidWorkspace& w);
void fluid_viscous(const Model& m, State& s, FluidWorkspace& w);
void fluid_pressure(const Model& m, State& s, FluidWorkspace& w);
void fluid_project(const Model& m, State& s, FluidWorkspace& w);
void fluid_store(const Model& m, State& s, FluidWorkspace& w);
// (fluid_stat, dt) => (dt): the fluid's time step, fixed or from the target CFL number.
void fluid_dt(const Model& m, State& s);
// The step fluid_dt takes from this state.
double next_dt(const Model& m, const State& s);
// The initial velocity (at rest, or a Taylor-Green vortex) into a fresh state.
void initial_velocity(const Model& m, State& s);

// nu k^2 for the box's longest wavelength: k = 2 pi / L along a periodic axis, pi / L between
// walls (at most the decay rate of the slowest viscous mode), the smallest over the axes.
double slowest_viscous_rate(const FluidParams& p);
// The largest step the viscous scheme allows: the explicit scheme's stability (0.9 of it), Crank-
// Nicolson's damping of the slowest mode (kCnModeLimit); infinite for backward Euler or nu = 0.
double viscous_dt_limit(const FluidParams& p);
// The adaptive step for a velocity field of rate = sum_a max|u_a| / h_a: cfl_target / rate,
// within viscous_dt_limit and dt_max.
double adaptive_dt(const FluidParams& p, double rate);
// dt sum_a max|u_a| / h_a, max|u_a| over the grid's faces and the velocities its boundaries
// impose (a lid's, an inflow's): a lid over a fluid at rest is the flow's speed to come. (Without
// the boundaries, a cavity at Re = 1e6 took a second step of dt_max = h^2 / nu = 41 L / U, whose
// CFL number was 0 at its start, and its kinetic energy came out 1.3e8 times U^2 L^2.)
double cfl_number(const FluidParams& p, const State& s, double dt);
// Where the state's flow is fastest, the CFL number's largest term |u_a| / h_a (or its first
// non-finite velocity), for a failure to name: the face's axis, the cell it bounds from below
// (the last cell for the high wall's faces), its centre and the velocity there.
struct FastestFace {
  int axis = -1;
  std::array<int64_t, 3> cell{};
  std::array<double, 3> x{};
  double u = 0;
};
FastestFace fastest_face(const FluidParams& p, const State& s);
// " at cell (i, j[, k]), x = (...): u_a = V" for a failure's message (units from the model).
std::string face_text(const Model& m, const FastestFace& f);
// max |velocity_a| imposed on the box's faces (walls' and inflows' velocities; 0 for periodic).
double boundary_speed(const Grid& g, int a);
// sum_a boundary_speed(a) / h_a: the rate of a fluid at rest between its walls, lids and inflows.
double boundary_rate(const Grid& g);
// A lower bound of the rate sum_a max|u_a| / h_a of the first steps from any state, known before
// any: per axis, the larger of its boundaries' speed and the imposed bulk velocity along the
// drive axis (the mean of u over the faces after the first step, so some face has at least it).
// A fixed step past the CFL limit with it fails in its first two steps; `what` names those that
// set it, with its verb ("... alone give").
double known_rate(const FluidParams& p, std::string* what = nullptr);
// The rate of the initial Taylor-Green vortex (fluid.initial), exactly that of the first state
// made from the scene; 0 for a fluid at rest. Not of a state restored or steered since.
double vortex_rate(const FluidParams& p);
// The rate a step from this state is held to: the state's own (kRate, stored by the last step or
// the initial field) or its boundaries' as the parameters give them now (steered since), the
// larger: a lid moving over a fluid still at rest limits the step as its flow will.
double step_rate(const FluidParams& p, const State& s);
// The relative change of the velocity per unit time L / U of the last observed step
// (kChangeRate times fluid.length_scale / fluid.velocity_scale), and whether it is below
// run.steady_tol: the steady state of run.stop_when_steady.
double change_rate(const FluidParams& p, const State& s);
bool is_steady(const FluidParams& p, const State& s);

}  // namespace silt::fluid
