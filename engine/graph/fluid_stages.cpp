// The fluid's stages (fluid/step.hpp). In a step:
//
//   choose_dt -> fluid_dt -> fluid_load -> fluid_substep x 3 -> fluid_store
//                                            fluid_momentum -> (fluid_viscous ->) fluid_pressure
//                                            -> fluid_project
//
// and in the setup graph, fluid_initial: the initial velocity of a fresh state.
#include <cmath>

#include "fluid/multigrid.hpp"
#include "fluid/step.hpp"
#include "graph/adders.hpp"
#include "silt/text.hpp"

namespace silt::graph {
namespace {

Access fluid_access() {
  const fluid::FluidFields f = fluid::fluid_fields();
  return {f.u[0], f.u[1], f.u[2], f.p, f.stat};
}

void diagnose_fluid(GraphBuilder& b) {
  b.diagnose(fluid::cfl_event(), [](const Model& m, const State& s, const EventSlot& e, StepFailure& f) {
    const auto& p = m.params.get<fluid::FluidParams>();
    f.stage = "fluid_load";
    if (e.first() == 0) {
      f.parameter = p.dt_fixed ? "fluid.dt" : "fluid.cfl";
      // (where: the contract names the particle or the cell, and the message named neither)
      const std::string where = fluid::face_text(m, fluid::fastest_face(p, s));
      f.message =
          "the fluid's CFL number dt sum |u|/h = " + format_past(e.value(), fluid::FluidParams::kCflLimit, 4) +
          " at step " + std::to_string(s.step) + " exceeds " + format_number(fluid::FluidParams::kCflLimit, 4) +
          ", the stability limit of RK3 advection (fastest" + (where.empty() ? std::string(" at the walls") : where) +
          "); " +
          (p.dt_fixed ? "reduce fluid.dt, or give fluid.cfl instead of it for the adaptive step" : "reduce fluid.cfl");
    } else {
      f.parameter = "fluid.viscous";
      f.message = "the explicit viscous term is unstable at this step: nu dt sum 1/h^2 = " +
                  format_past(e.value(), fluid::FluidParams::kViscousLimit, 4) + " exceeds " +
                  format_number(fluid::FluidParams::kViscousLimit, 4) +
                  "; reduce fluid.dt or the viscosity, or use fluid.viscous = \"crank_nicolson\"";
    }
  });
  b.diagnose(fluid::nonfinite_event(), [](const Model& m, const State& s, const EventSlot& e, StepFailure& f) {
    const auto& p = m.params.get<fluid::FluidParams>();
    // The knob of the step is the key that sets it; a pressure-gradient drive may be what overflowed.
    const std::string step_key = p.dt_fixed ? "fluid.dt" : "fluid.cfl";
    const bool driven = p.drive == fluid::Drive::kPressure;
    const std::string gradient =
        driven ? "fluid.pressure_gradient (" + format_number(p.pressure_gradient, 4) + " Pa/m)" : "";
    f.stage = "fluid_store";
    f.parameter = step_key;
    if (e.first() == 1) {
      // Finite velocities whose squares over the grid overflow: a drive (or a wall) far too strong.
      f.parameter = driven ? "fluid.pressure_gradient" : step_key;
      f.message = "the fluid's speed at step " + std::to_string(s.step) +
                  ", sum max|u|/h = " + format_number(e.value(), 4) +
                  " 1/s, is too fast for double precision: its kinetic energy and " + "enstrophy, squares over the " +
                  format_number(static_cast<double>(p.grid.cells()), 4) + " cells, overflow; " +
                  (driven ? "lower " + gradient : "reduce " + step_key);
      return;
    }
    const fluid::FastestFace first = fluid::fastest_face(p, s);
    f.message = "the fluid velocity is no longer finite at step " + std::to_string(s.step) +
                (std::isfinite(first.u) ? std::string() : " (first" + fluid::face_text(m, first) + ")") +
                ": the flow is under-resolved or the step too large; reduce " + step_key + ", or use more fluid.cells" +
                (driven ? ", or a lower " + gradient : "");
  });
  b.diagnose(fluid::solve_event(), [](const Model& m, const State&, const EventSlot& e, StepFailure& f) {
    const auto& p = m.params.get<fluid::FluidParams>();
    f.stage = "fluid_pressure";
    // A residual that stagnated, or reached round-off (1e-12 and below, which grows with the grid)
    // with the limit: more iterations do not lower it, the tolerance is the knob.
    const bool stalled =
        static_cast<linalg::SolveStatus>(e.first()) == linalg::SolveStatus::kStagnated || e.value() < 1e-12;
    f.parameter = stalled ? "fluid.tolerance" : "fluid.max_iterations";
    f.message = "the pressure solve (multigrid CG) did not converge: relative residual " + format_number(e.value(), 4) +
                " above fluid.tolerance = " + format_number(p.tolerance, 4) +
                (stalled ? "; the residual stalls at round-off there on this grid: raise fluid.tolerance"
                         : "; raise fluid.max_iterations or fluid.tolerance, or use fluid.projection = \"fft\"");
    if (const std::string note = fluid::coarsening_note(p.grid); !note.empty()) f.message += "; " + note;
  });
}

}  // namespace

void add_fluid_stages(GraphBuilder& b) {
  const fluid::FluidFields f = fluid::fluid_fields();
  if (b.phase() == Phase::kSetup) {
    b.add(
        "fluid_initial",
        [](const Model& m, State& s) {
          if (s.module_field(fluid::fluid_fields().stat).empty()) fluid::initial_velocity(m, s);
        },
        fluid_access(), fluid_access());  // (a state that has its fields keeps them: it reads them)
    return;
  }
  auto& w = b.workspaces().get<fluid::FluidWorkspace>();
  const bool implicit = b.model().params.get<fluid::FluidParams>().viscous != fluid::Viscous::kExplicit;
  const int dt = b.add("fluid_dt", &fluid::fluid_dt, {fid::dt, f.stat}, {fid::dt});
  b.light(dt);
  b.after(dt, b.find("choose_dt"), "replaces the scene's step by the fluid's");
  Access reads = fluid_access();
  reads.push_back(fid::dt);
  const int load = b.add("fluid_load", [&w](const Model& m, State& s) { fluid::fluid_load(m, s, w); }, reads, {f.stat});
  b.after(load, dt, "advances by this step's dt");
  // The three Runge-Kutta substeps: the stages share the workspace's padded velocity, so each
  // waits for the one before it.
  const int loop = b.loop("fluid_substep", 3, [&w, implicit, f](GraphBuilder& lb) {
    auto stage = [&](const char* name, void (*fn)(const Model&, State&, fluid::FluidWorkspace&), Access writes) {
      const int i = lb.add(
          name, [&w, fn](const Model& m, State& s) { fn(m, s, w); }, {}, std::move(writes));
      lb.carries_workspace(i);
      return i;
    };
    const int momentum = stage("fluid_momentum", &fluid::fluid_momentum, {});
    int before = momentum;
    if (implicit) {
      const int viscous = stage("fluid_viscous", &fluid::fluid_viscous, {});
      lb.after(viscous, momentum, "solves for the u* the momentum stage predicted");
      before = viscous;
    }
    const int pressure = stage("fluid_pressure", &fluid::fluid_pressure, {f.stat});
    lb.after(pressure, before, "takes the divergence of u*");
    const int project = stage("fluid_project", &fluid::fluid_project, {});
    lb.after(project, pressure, "subtracts the gradient of the pressure just solved");
  });
  b.after(loop, load, "starts from the loaded velocity");
  const int store = b.add(
      // Reads what it writes: a step stopped by an event leaves the fields as they were.
      "fluid_store", [&w](const Model& m, State& s) { fluid::fluid_store(m, s, w); }, fluid_access(), fluid_access());
  b.after(store, loop, "stores the velocity of the last substep");
  diagnose_fluid(b);
}

}  // namespace silt::graph
