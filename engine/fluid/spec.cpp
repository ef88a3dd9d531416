// The fluid module as the rest of silt sees it (silt/module.hpp): `silt check`'s description, live
// steering, the memory estimate, the checks of a restored state, the summary.
#include <sstream>

#include "fluid/module.hpp"
#include "fluid/multigrid.hpp"
#include "fluid/step.hpp"
#include "silt/text.hpp"

namespace silt::fluid {
namespace {

// Bytes per (padded) cell a run holds at its peak, as measured after steps (the memory estimate
// test): the state's velocity and pressure and the restart point's copy of them; the step's
// padded velocity, predictor, previous advection and boundary Laplacian, the increment and the
// kinetic pressure, two cell vectors; the solvers' (the transforms' line buffers: about 3 doubles a
// cell in 2D on two threads, more on more, under 1 in 3D; CG's vectors and multigrid hierarchy); and a sample's padded
// copy of the velocity and pressure with the vorticity (frames, enstrophy), made while all that is held.
double bytes_per_cell(const FluidParams& p) {
  const int D = p.grid.dim;
  double doubles = 2 * (D + 1) + 4 * D + 2 + 2;
  doubles += p.projection == Projection::kMultigridCg ? 8 : (D == 2 ? 4 : 1);
  doubles += (D + 1) + (D == 3 ? 3 : 1);
  return 8 * doubles;
}

double padded_cells(const FluidParams& p) {
  double c = 1;
  for (int a = 0; a < p.grid.dim; ++a) c *= static_cast<double>(p.grid.n[a] + 3);
  return c;
}

double fluid_memory_bytes(const Model& m) {
  const FluidParams& p = m.params.get<FluidParams>();
  double points = 0;
  for (const LineProbe& l : p.lines) points += l.points;
  return bytes_per_cell(p) * padded_cells(p) + points * summary_memory_per_point(p.grid.dim);
}

}  // namespace

std::string describe_fluid(const Model& m) {
  const FluidParams& p = m.params.get<FluidParams>();
  const Grid& g = p.grid;
  std::ostringstream o;
  o.precision(5);
  o << "fluid        " << g.n[0];
  for (int a = 1; a < m.dim; ++a) o << " x " << g.n[a];
  o << " cells of h = " << g.h[0] << m.unit("m") << " (" << static_cast<double>(g.cells()) << " cells, "
    << bytes_per_cell(p) * padded_cells(p) / static_cast<double>(g.cells()) << " bytes per cell, "
    << bytes_per_cell(p) * padded_cells(p) / (1 << 20) << " MiB)\n";
  if (const double probes = fluid_memory_bytes(m) - bytes_per_cell(p) * padded_cells(p); probes > 0)
    o << "             line probes: " << std::llround(probes / summary_memory_per_point(g.dim)) << " points, about "
      << probes / (1 << 20) << " MiB as the summary is written\n";
  o << "             rho = " << p.density << m.unit("kg/m^3") << ", mu = " << p.viscosity << m.unit("Pa s")
    << " (nu = " << p.nu() << m.unit("m^2/s") << "); Re = U L / nu = "
    << (p.nu() > 0 ? format_number(p.velocity_scale * p.length_scale / p.nu()) : std::string("inf (inviscid)"))
    << " (U = " << p.velocity_scale << m.unit("m/s") << ", L = " << p.length_scale << m.unit("m") << ")\n";
  o << "             faces:";
  for (int a = 0; a < m.dim; ++a)
    for (int side = 0; side < 2; ++side) {
      const Bc& bc = g.bc[a][side];
      o << " " << face_names()[2 * a + side] << " " << bc_name(bc.type);
      if ((bc.type == BcType::kNoSlip || bc.type == BcType::kInflow) &&
          (bc.velocity[0] != 0 || bc.velocity[1] != 0 || bc.velocity[2] != 0)) {
        o << " [";
        for (int c = 0; c < m.dim; ++c) o << (c ? ", " : "") << bc.velocity[c];
        o << "]" << (bc.parabolic ? " parabolic" : "");
      }
    }
  o << "\n";
  const double inv = g.inv_h2_sum();
  const double dt = p.dt;
  const char* scheme = p.viscous == Viscous::kExplicit        ? "explicit"
                       : p.viscous == Viscous::kCrankNicolson ? "Crank-Nicolson"
                                                              : "backward Euler";
  o << "             RK3 (Wray), viscous " << scheme << ", projection "
    << (p.projection == Projection::kFft ? "by fast transforms (FFTW)" : "by multigrid CG to ")
    << (p.projection == Projection::kFft ? std::string() : format_number(p.tolerance, 3)) << "\n";
  o << "             time step " << (p.dt_fixed ? "fixed " : "adaptive from ") << dt << m.unit("s")
    << (p.dt_fixed ? std::string()
                   : " (target CFL " + format_number(p.cfl_target, 3) + ", at most " + format_number(p.dt_max, 4) +
                         m.unit("s") + ")")
    << "; CFL at U: " << dt * m.dim * p.velocity_scale / g.h[0] << " (limit " << FluidParams::kCflLimit
    << (p.dt_fixed && dt * m.dim * p.velocity_scale / g.h[0] > FluidParams::kCflLimit
            ? "; a flow at U along every axis passes it, and the run stops at the step that does"
            : "")
    << "); viscous number nu dt sum 1/h^2 = " << p.nu() * dt * inv
    << (p.viscous == Viscous::kExplicit ? " (limit " + format_number(FluidParams::kViscousLimit, 2) + ")"
                                        : std::string(" (implicit: no limit)"))
    << "; nu dt k^2 at the box's longest wavelength = " << dt * slowest_viscous_rate(p)
    << (p.viscous == Viscous::kCrankNicolson
            ? " (Crank-Nicolson: at most " + format_number(FluidParams::kCnModeLimit, 2) + ")"
            : std::string())
    << "\n";
  if (p.drive == Drive::kPressure)
    o << "             driven by -dp/d"
      << "xyz"[p.drive_axis] << " = " << p.pressure_gradient << m.unit("Pa/m") << "\n";
  if (p.drive == Drive::kFlowRate)
    o << "             driven at a bulk velocity " << p.bulk_velocity << m.unit("m/s") << " along "
      << "xyz"[p.drive_axis] << "\n";
  if (const std::string note = fluid_note(m, p.dt); !note.empty()) o << "             note: " << note << "\n";
  // (a 1021^2 cavity under multigrid CG ran 30 s and failed without a word of its grid)
  if (p.projection == Projection::kMultigridCg)
    if (const std::string note = coarsening_note(g); !note.empty()) o << "             note: " << note << "\n";
  return o.str();
}

// The steered values are in the fresh model's parameters, which steer() takes over whole, and
// the step in its dt (the core's steer); what lies outside them: whether the step adapts.
std::string steer_fluid(Model& m, const Model& fresh) {
  m.adaptive_dt = fresh.adaptive_dt;
  m.dt_key = fresh.dt_key;
  return "";
}

const ModuleSpec& module() {
  static const ModuleSpec spec = [] {
    ModuleSpec s;
    s.name = "fluid";
    s.doc = "incompressible Navier-Stokes on a staggered grid (RK3, projection by fast transforms)";
    s.keys = fluid_keys();
    mark_initial(s.keys, {"fluid.initial", "fluid.initial_velocity"});
    // One drive: a flow rate given over a scene's pressure gradient replaces it (before, the
    // pressure gradient kept driving while the bulk velocity set the velocity scale).
    // A fixed step or the adaptive one's target and cap: fluid.dt given over a scene's fluid.cfl
    // replaces it (before, the target was kept and did nothing), and fluid.cfl steered over a
    // fixed step makes it adaptive again.
    s.rules = {KeyRule::one_of({{"fluid.pressure_gradient"}, {"fluid.bulk_velocity"}}),
               KeyRule::one_of({{"fluid.reynolds"}, {"fluid.viscosity"}}),
               KeyRule::one_of({{"fluid.dt"}, {"fluid.cfl", "fluid.dt_max"}})};
    s.fields = {{"fluid_u", Extent::kFaceX, "m/s", "x velocity on the x faces; fluid_store"},
                {"fluid_v", Extent::kFaceY, "m/s", "y velocity on the y faces; fluid_store"},
                {"fluid_w", Extent::kFaceZ, "m/s", "z velocity on the z faces (3D); fluid_store"},
                {"fluid_p", Extent::kCell, "Pa", "pressure at the cell centres (of the last projection); fluid_store"},
                {"fluid_stat", Extent::kFree, "",
                 "next dt, div max, CFL, change rate, solver numbers (fluid/step.hpp); fluid_load, fluid_pressure, "
                 "fluid_store"}};
    s.events = {"fluid_cfl", "fluid_nonfinite", "fluid_solve"};
    s.observables = fluid_observables();
    s.enabled = [](const SceneDesc& d) { return d.has_table("fluid"); };
    s.compile = compile_fluid;
    s.finish = finish_fluid;
    s.describe = describe_fluid;
    s.steer = steer_fluid;
    // Said once, before the first step (the adaptive step where the run starts).
    // Of the model's step, as `check` prints it: a state at step 0 holds the step of its last
    // preparation, before a steered fluid.dt or fluid.cfl or a reset.
    s.notice = [](const Model& m, const State& st) {
      return st.step == 0 ? fluid_note(m, m.params.get<FluidParams>().dt) : std::string();
    };
    s.memory_bytes = fluid_memory_bytes;
    s.check_state = [](const Model&, const State& st) -> std::string {
      // kStatCount - 1: a checkpoint written before kChangeRate (fluid_load appends it).
      const size_t n = st.module_field(fluid_fields().stat).size();
      // The velocities and the pressure are finite: the reader checks every field's values.
      if (n != kStatCount && n != kStatCount - 1) return "fluid_stat has the wrong length";
      return "";
    };
    // The pressure solves, as INTERFACE.md's "solver" group (transforms: no iterations).
    s.summary_group = "solver";
    s.summary_counts = {"solves", "iters_max", "refactorisations"};
    s.summary = [](const Model&, const State& st) {
      const auto& v = st.module_field(fluid_fields().stat);
      std::vector<std::pair<std::string, double>> out;
      if (v.size() < kStatCount - 1) return out;
      out = {{"solves", v[kSolves]},
             {"iters_mean", v[kSolves] > 0 ? v[kItersSum] / v[kSolves] : 0.0},
             {"iters_max", v[kItersMax]},
             {"refactorisations", 0.0}};
      return out;
    };
    s.grid_fields = [](const Model& m, const State& st, std::string_view only) {
      return cell_fields(m.params.get<FluidParams>(), st, only);
    };
    s.lines = line_samples;
    s.steady = [](const Model& m, const State& st) { return is_steady(m.params.get<FluidParams>(), st); };
    return s;
  }();
  return spec;
}

}  // namespace silt::fluid
