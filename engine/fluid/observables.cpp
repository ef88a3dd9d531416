// The fluid's observables (names of INTERFACE.md).
#include "fluid/module.hpp"
#include "fluid/step.hpp"

namespace silt::fluid {
namespace {

double stat(const ObservableContext& c, FluidStat k) {
  const auto& v = c.s.module_field(fluid_fields().stat);
  return static_cast<int>(v.size()) > k ? v[k] : 0.0;
}

const FluidParams& params(const ObservableContext& c) { return c.m.params.get<FluidParams>(); }

}  // namespace

std::vector<ObservableSpec> fluid_observables() {
  std::vector<ObservableSpec> specs = {
      {"fluid.ke", "J", "fluid kinetic energy (rho/2) integral |u|^2 (per unit depth in 2D)",
       [](const ObservableContext& c, const ObservableArgs&) { return kinetic_energy(params(c), c.s); }},
      {"fluid.enstrophy", "m^3/s^2", "(1/2) integral |omega|^2 (per unit depth in 2D)",
       [](const ObservableContext& c, const ObservableArgs&) { return enstrophy(params(c), c.s); }},
      {"fluid.div_max", "1/s", "largest |div u| after the last projection",
       [](const ObservableContext& c, const ObservableArgs&) { return stat(c, kDivMax); }},
      {"fluid.cfl", "", "CFL number dt sum_a max|u_a| / h_a of the last step",
       [](const ObservableContext& c, const ObservableArgs&) { return stat(c, kCfl); }},
      {"fluid.dt", "s", "the fluid's time step (the next one when adaptive)",
       [](const ObservableContext& c, const ObservableArgs&) { return next_dt(c.m, c.s); }},
      {"fluid.change_rate", "",
       "max |u(t + dt) - u(t)| / (max |u| dt) of the last step, in units of U / L: the relative change of the "
       "velocity per unit time L / U (run.stop_when_steady)",
       [](const ObservableContext& c, const ObservableArgs&) { return change_rate(params(c), c.s); }},
      {"fluid.pressure_gradient", "Pa/m",
       "mean -dp/dx along the drive axis: the one imposed (from the state given, as the parameters have it now), or "
       "the one that held the flow rate over the last step",
       [](const ObservableContext& c, const ObservableArgs&) {
         const FluidParams& p = params(c);
         return p.drive == Drive::kPressure ? p.pressure_gradient : stat(c, kDriveGradient);
       }},
      {"fluid.bulk_velocity", "m/s", "mean velocity along the drive axis over the domain",
       [](const ObservableContext& c, const ObservableArgs&) {
         const FluidParams& p = params(c);
         return mean_velocity(p, c.s, p.drive_axis < p.grid.dim ? p.drive_axis : 0);
       }},
      {"solver.iters", "", "iterations of the last pressure solve (0 for the fast transforms)",
       [](const ObservableContext& c, const ObservableArgs&) { return stat(c, kIters); }},
      {"solver.residual", "", "relative residual of the last pressure solve (0 for the fast transforms)",
       [](const ObservableContext& c, const ObservableArgs&) { return stat(c, kResidual); }},
  };
  // (the driving gradient of a flow rate is the last step's too; an imposed one is the parameter)
  for (ObservableSpec& o : specs)
    o.of_last_step = o.pattern == "fluid.div_max" || o.pattern == "fluid.cfl" || o.pattern == "fluid.change_rate" ||
                     o.pattern == "fluid.pressure_gradient" || o.pattern.starts_with("solver.");
  return specs;
}

}  // namespace silt::fluid
