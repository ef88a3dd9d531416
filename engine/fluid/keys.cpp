// The fluid's scene keys ([fluid], [fluid.boundary], [[output.lines]]).
#include "fluid/module.hpp"
#include "silt/text.hpp"

namespace silt::fluid {

const std::array<const char*, 6>& face_names() {
  static const std::array<const char*, 6> f = {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};
  return f;
}

std::vector<KeySpec> fluid_keys() {
  using K = KeyType;
  using S = std::vector<std::string>;
  // clang-format off
  std::vector<KeySpec> s = {
      {"fluid.cells", K::kRealList, std::nullopt, Range::closed(2, 1e6), "", false, {}, "Cells of the grid per axis, [nx, ny] or [nx, ny, nz]: uniform spacing, the domain's length / cells (equal along every axis up to 1e-9)."},
      {"fluid.density", K::kReal, Value(1.0), Range::positive(), "kg/m^3", false, {}, "Density rho of the fluid."},
      {"fluid.viscosity", K::kReal, std::nullopt, Range::non_negative(), "Pa s", true, {}, "Dynamic viscosity mu; nu = mu / rho. Or give fluid.reynolds."},
      {"fluid.reynolds", K::kReal, std::nullopt, Range::positive(), "", true, {}, "Dimensionless form: Re = U L / nu with U = fluid.velocity_scale and L = fluid.length_scale (the viscosity follows; fluid.dt is then in units of L / U)."},
      {"fluid.velocity_scale", K::kReal, std::nullopt, Range::positive(), "m/s", false, {}, "U of the Reynolds number (default: the fastest wall or inflow, else the Taylor-Green amplitude, else 1)."},
      {"fluid.length_scale", K::kReal, std::nullopt, Range::positive(), "m", false, {}, "L of the Reynolds number (default: the domain's length along x)."},
      {"fluid.dt", K::kReal, std::nullopt, Range::positive(), "s", true, {}, "A fixed fluid time step (in units of L / U with fluid.reynolds); default: adaptive from fluid.cfl."},
      {"fluid.cfl", K::kReal, Value(0.5), Range::open_closed(0, 1.5), "", true, {}, "Adaptive step: the target CFL number dt sum_a max|u_a| / h_a, the walls' and inflows' velocities included (RK3 is stable below sqrt(3); runs stop above 1.6)."},
      {"fluid.dt_max", K::kReal, std::nullopt, Range::positive(), "s", true, {}, "Adaptive step: the largest (in units of L / U with fluid.reynolds; default: L / U / 10 in a fluid at rest, or one viscous time h^2 / nu)."},
      {"fluid.viscous", K::kString, Value(std::string("crank_nicolson")), Range::any(), "", false, S{"crank_nicolson", "backward_euler", "explicit"}, "Viscous term: Crank-Nicolson (implicit, second order; Helmholtz equations solved by transforms; the step at most 1 / (nu k^2) for the box's longest wavelength, which it damps too little beyond), backward Euler (implicit, first order, damps every mode: no viscous step limit; for Re << 1) or explicit (RK3, nu dt sum 1/h^2 <= 0.6)."},
      {"fluid.projection", K::kString, Value(std::string("fft")), Range::any(), "", false, S{"fft", "multigrid_cg"}, "Pressure Poisson solver: fast transforms (FFTW, direct) or CG preconditioned by a multigrid V-cycle (the reference)."},
      {"fluid.tolerance", K::kReal, Value(1e-10), Range::closed(1e-15, 1e-2), "", true, {}, "multigrid_cg: relative residual at which CG stops (at least 1e-15: below, round-off in the residual itself; on large grids the residual stalls above it, near 1e-14 at 64^2, and the run stops naming this key)."},
      {"fluid.max_iterations", K::kInt, Value(int64_t{200}), Range::closed(1, 1e6), "", true, {}, "multigrid_cg: iterations at most; past them the run stops with a numerical failure."},
      {"fluid.initial", K::kString, Value(std::string("rest")), Range::any(), "", false, S{"rest", "taylor_green"}, "Initial velocity: at rest, or the Taylor-Green vortex u = U0 sin(kx) cos(ky) cos(kz), v = -c U0 cos sin cos, k = 2 pi / L per axis, c = kx / ky as the grid differentiates, sin(kx hx / 2) / hx over sin(ky hy / 2) / hy (periodic box; divergence-free on the grid)."},
      {"fluid.initial_velocity", K::kReal, Value(1.0), Range::positive(), "m/s", false, {}, "Taylor-Green amplitude U0."},
      {"fluid.drive_axis", K::kString, Value(std::string("x")), Range::any(), "", false, S{"x", "y", "z"}, "Periodic axis along which a pressure gradient or a flow rate drives the flow (a channel)."},
      {"fluid.pressure_gradient", K::kReal, std::nullopt, Range::any(), "Pa/m", true, {}, "Pressure-driven flow: the mean -dp/dx along fluid.drive_axis, a uniform body force."},
      {"fluid.bulk_velocity", K::kReal, std::nullopt, Range::any(), "m/s", true, {}, "Flow-driven: the mean velocity along fluid.drive_axis, held by the mean pressure gradient it needs."},
      {"run.stop_when_steady", K::kBool, Value(false), Range::any(), "", false, {}, "Stop when the fluid is steady: its velocity changes by less than run.steady_tol (relative, per unit time L / U), tested every limits.check_every steps; the summary's status is then steady."},
      {"run.steady_tol", K::kReal, Value(1e-6), Range::positive(), "", false, {}, "Steady state: max |u(t + dt) - u(t)| / (max |u| dt) in units of U / L (fluid.velocity_scale / fluid.length_scale), the observable fluid.change_rate."},
      {"output.lines[].name", K::kString, std::nullopt, Range::any(), "", false, {}, "Line probe: its name in the summary's \"lines\"."},
      {"output.lines[].field", K::kString, std::nullopt, Range::any(), "", false, S{"u", "v", "w", "p", "vorticity"}, "Line probe: the field sampled (vorticity: its z component in 2D, its magnitude in 3D)."},
      {"output.lines[].from", K::kRealList, std::nullopt, Range::any(), "m", false, {}, "Line probe: the segment's start."},
      {"output.lines[].to", K::kRealList, std::nullopt, Range::any(), "m", false, {}, "Line probe: the segment's end."},
      {"output.lines[].points", K::kInt, Value(int64_t{101}), Range::closed(2, 1e6), "", false, {}, "Line probe: points along the segment, both ends included."},
  };
  // clang-format on
  // What compile() chose where the scene is silent (`params`, `get`).
  auto chosen = [](double (*of)(const FluidParams&)) {
    return [of](const Model& m) {
      return m.module_on("fluid") ? format_number(of(m.params.get<FluidParams>())) : std::string();
    };
  };
  for (KeySpec& k : s) {
    if (k.path == "fluid.viscosity") k.computed = chosen([](const FluidParams& p) { return p.viscosity; });
    // (a scene given by its viscosity, or one whose fluid.reynolds a `set fluid.viscosity` replaced)
    if (k.path == "fluid.reynolds")
      k.computed = [](const Model& m) {
        if (!m.module_on("fluid")) return std::string();
        const FluidParams& p = m.params.get<FluidParams>();
        return p.nu() > 0 ? format_number(p.velocity_scale * p.length_scale / p.nu()) : std::string("inf (inviscid)");
      };
    if (k.path == "fluid.dt") k.computed = chosen([](const FluidParams& p) { return p.dt / p.time_unit(); });
    if (k.path == "fluid.dt_max") k.computed = chosen([](const FluidParams& p) { return p.dt_max / p.time_unit(); });
    // Times are in units of L / U where the scene gives fluid.reynolds (spec.cpp).
    if (k.path == "fluid.dt" || k.path == "fluid.dt_max")
      k.unit_in = [](const Model& m) {
        return m.module_on("fluid") && m.params.get<FluidParams>().dimensionless ? std::string("L/U")
                                                                                 : std::string("s");
      };
    if (k.path == "fluid.velocity_scale") k.computed = chosen([](const FluidParams& p) { return p.velocity_scale; });
    if (k.path == "fluid.length_scale") k.computed = chosen([](const FluidParams& p) { return p.length_scale; });
  }
  for (const char* f : face_names()) {
    const std::string b = std::string("fluid.boundary.") + f;
    s.push_back(
        {b, K::kString, std::nullopt, Range::any(), "", false,
         S{"periodic", "no_slip", "free_slip", "inflow", "outflow"},
         "Condition on this face (default: periodic along a periodic axis, else no_slip). inflow: the velocity of " +
             b + "_velocity; outflow: zero normal gradient and p = 0 (on the high faces only)."});
    s.push_back({b + "_velocity",
                 K::kRealList,
                 std::nullopt,
                 Range::any(),
                 "m/s",
                 true,
                 {},
                 "no_slip: the wall's tangential velocity (a lid); inflow: the inflow velocity (its peak when "
                 "parabolic), its normal component into the box."});
    s.push_back({b + "_profile", K::kString, Value(std::string("plug")), Range::any(), "", false,
                 S{"plug", "parabolic"},
                 "inflow: a uniform velocity, or a parabola vanishing on the walls of the other axes."});
  }
  return s;
}

}  // namespace silt::fluid
