// The fluid module: a scene with [fluid] has an incompressible Newtonian fluid on a staggered
// grid over its domain (Izard 2014 sec. 2.2; fluid/step.hpp). It adds its keys, its fields (the
// velocity on the faces, the pressure at the cell centres, its numbers), its observables, its
// grid fields for frames and VTK files, its line probes for the summary, and its events.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/machine.hpp"
#include "fluid/module.hpp"
#include "fluid/step.hpp"
#include "silt/simulation.hpp"
#include "silt/text.hpp"

namespace silt::fluid {
namespace {

BcType bc_type(const std::string& s) {
  if (s == "periodic") return BcType::kPeriodic;
  if (s == "free_slip") return BcType::kFreeSlip;
  if (s == "inflow") return BcType::kInflow;
  if (s == "outflow") return BcType::kOutflow;
  return BcType::kNoSlip;
}

// The cells of a grid scaled alike along every axis to take about `room` bytes where it needs
// `need`: the memory is about proportional to the cells (the caller leaves a margin: at 0.9 of
// the memory free, 4000^3 cells scaled to 442^3, which needed 21 GiB of 23).
std::string fitting_cells(const Model& m, const Grid& g, double need, double room) {
  const double f = std::pow(room / need, 1.0 / m.dim);
  std::string text = "at most about [";
  for (int a = 0; a < m.dim; ++a)
    text += (a ? ", " : "") + format_number(std::max(1.0, std::floor(static_cast<double>(g.n[a]) * f)), 15);
  return text + "]";
}

// What gives every axis x's spacing: the cells that do where the domain's lengths are whole
// multiples of it, else the domain lengths that the nearest whole numbers of cells would need.
std::string same_spacing_advice(const Model& m, const Grid& g) {
  std::string cells = "[" + std::to_string(g.n[0]), lengths;
  bool whole = true;
  for (int a = 1; a < m.dim; ++a) {
    const double n = m.box.len[a] / g.h[0], k = std::max(1.0, std::round(n));
    whole = whole && std::abs(n - k) <= 1e-9 * n;
    cells += ", " + format_number(k, 15);
    if (std::abs(n - k) > 1e-9 * n)
      lengths += std::string(lengths.empty() ? "" : ", ") + format_number(k * g.h[0], 10) + " m along " +
                 std::string(1, "xyz"[a]) + " (" + format_number(k, 15) + " cells)";
  }
  cells += "]";
  if (whole) return "give fluid.cells = " + cells;
  std::string text = "no whole number of cells of " + format_number(g.h[0], 10) + " m fits the domain: make it " +
                     lengths + ", or give other cells along x";
  // The count along x nearest to the one given whose spacing divides every length.
  const auto fits = [&](int64_t nx) {
    std::string c = "[" + std::to_string(nx);
    for (int a = 1; a < m.dim; ++a) {
      const double n = m.box.len[a] * static_cast<double>(nx) / m.box.len[0], k = std::round(n);
      if (k < 1 || std::abs(n - k) > 1e-9 * n) return std::string();
      c += ", " + format_number(k, 15);
    }
    return c + "]";
  };
  for (int64_t j = 1; j <= 4 * g.n[0] && j <= 100000; ++j)
    for (const int64_t nx : {g.n[0] - j, g.n[0] + j})
      if (nx >= 1)
        if (const std::string c = fits(nx); !c.empty()) return text + " (fluid.cells = " + c + ")";
  return text;
}

// Grid: cells, uniform spacing, and the condition of each face.
void compile_grid(const SceneDesc& d, const Model& m, Grid& g) {
  g.dim = m.dim;
  const auto cells = d.reals("fluid.cells");
  if (static_cast<int>(cells.size()) != m.dim)
    d.fail("fluid.cells", "needs " + std::to_string(m.dim) + " entries (cells per axis)");
  for (int a = 0; a < m.dim; ++a) {
    if (cells[a] != std::floor(cells[a])) d.fail("fluid.cells", "cells per axis are whole numbers");
    g.n[a] = static_cast<int64_t>(cells[a]);
    g.lo[a] = m.box.lo[a];
    g.h[a] = m.box.len[a] / static_cast<double>(g.n[a]);
  }
  // The kinetic energy and the enstrophy are integrals over the cells: a domain of 1e300 m in 2D
  // (1e110 m in 3D) gave them inf from the first sample, and the CFL number NaN.
  if (!std::isnormal(g.cell_volume()))
    d.fail(d.first_given({"domain.hi", "domain.lo"}, "domain.hi"),
           "the grid's cells, of " + format_number(g.cell_volume(), 4) + (m.dim == 3 ? " m^3" : " m^2") +
               " each, are beyond what double precision resolves (the fluid's integrals over them would be 0 or inf)");
  // (the refusal named the two spacings only, and to 4 digits they looked equal at 1e-7 apart)
  for (int a = 1; a < m.dim; ++a)
    if (std::abs(g.h[a] - g.h[0]) > 1e-9 * g.h[0])
      d.fail("fluid.cells", "the grid spacing must be the same along every axis (to 1e-9 of it): " +
                                format_number(g.h[0], 10) + " m along x, " + format_number(g.h[a], 10) + " m along " +
                                std::string(1, "xyz"[a]) + " (domain length / cells); " + same_spacing_advice(m, g));
  for (int a = 0; a < m.dim; ++a) {
    for (int side = 0; side < 2; ++side) {
      const std::string key = std::string("fluid.boundary.") + face_names()[2 * a + side];
      Bc& bc = g.bc[a][side];
      bc.type = d.has(key) ? bc_type(d.string(key)) : (m.box.periodic[a] ? BcType::kPeriodic : BcType::kNoSlip);
      if ((bc.type == BcType::kPeriodic) != m.box.periodic[a])
        d.fail(d.has(key) ? key : "domain.periodic",
               std::string("a face of a ") + (m.box.periodic[a] ? "periodic" : "non-periodic") + " axis (" +
                   std::string(1, "xyz"[a]) + ") cannot be " + (m.box.periodic[a] ? "anything but " : "") + "periodic");
      if (bc.type == BcType::kOutflow && side == 0)
        d.fail(key, "an outflow is on a high face (x_hi, y_hi, z_hi): put the inflow on the low face");
      if (d.has(key + "_velocity")) {
        const auto v = d.reals(key + "_velocity");
        if (static_cast<int>(v.size()) != m.dim)
          d.fail(key + "_velocity", "needs " + std::to_string(m.dim) + " entries");
        if (bc.type != BcType::kNoSlip && bc.type != BcType::kInflow)
          d.fail(key + "_velocity", "a velocity is given to a no_slip wall (a lid) or an inflow");
        for (int c = 0; c < m.dim; ++c) bc.velocity[c] = v[c];
        if (bc.type == BcType::kNoSlip && v[a] != 0)
          d.fail(key + "_velocity", "a wall moves along itself only: its normal component must be 0");
        // (An inflow whose velocity left the box took fluid out at a set rate, with the outflow
        // face pulling it back in: the run blew up without a word.)
        if (bc.type == BcType::kInflow && !(side == 0 ? v[a] > 0 : v[a] < 0))
          d.fail(key + "_velocity", "an inflow's normal component enters the box (" +
                                        std::string(side == 0 ? "> 0 on a low face" : "< 0 on a high face") +
                                        "), here " + format_number(v[a], 4) +
                                        "; fluid leaves the box through an outflow face");
      } else if (bc.type == BcType::kInflow) {
        d.fail(key, "an inflow needs " + key + "_velocity");
      }
      // (Read for an inflow only: a profile given to another face is refused as unused.)
      if (bc.type == BcType::kInflow) bc.parabolic = d.string(key + "_profile") == "parabolic";
    }
  }
  std::string inflow;  // the key of the first inflow face
  bool outflow = false;
  for (int a = 0; a < m.dim; ++a)
    for (int side = 0; side < 2; ++side) {
      if (g.bc[a][side].type == BcType::kInflow && inflow.empty())
        inflow = std::string("fluid.boundary.") + face_names()[2 * a + side];
      outflow |= g.bc[a][side].type == BcType::kOutflow;
    }
  if (!inflow.empty() && !outflow) d.fail(inflow, "an inflow needs an outflow somewhere: the fluid is incompressible");
}

// The velocity scale U of the dimensionless form: the fastest wall or inflow, else U0.
double default_velocity_scale(const FluidParams& p) {
  double u = 0;
  for (int a = 0; a < p.grid.dim; ++a) u = std::max(u, boundary_speed(p.grid, a));
  if (u == 0 && p.initial == Initial::kTaylorGreen) u = p.initial_velocity;
  if (u == 0) u = std::abs(p.bulk_velocity);
  return u > 0 ? u : 1.0;
}

// A speed given at `key` whose squares over the grid would overflow: its kinetic energy and
// enstrophy ((|u| / h)^2 summed over the cells) infinite from the first sample (a lid at 1e155
// m/s ran, and its stats showed inf).
void check_speed(const SceneDesc& d, const std::string& key, double v, const Grid& g, double density) {
  if (!g.squares_overflow(std::abs(v) / g.h_min(), density)) return;
  d.fail(key, key + " = " + format_number(v, 4) + " m/s: the flow's kinetic energy or enstrophy, squares over the " +
                  format_number(static_cast<double>(g.cells()), 4) + " cells, overflows double precision");
}

// What may change while running: viscosity (or Re), walls' and inflows' velocities, the drive,
// the time step and the target CFL, the solver's tolerance.
void compile_steerable(const SceneDesc& d, const Model& m, FluidParams& p) {
  p.density = d.real("fluid.density");
  if (!std::isnormal(p.density))
    d.fail("fluid.density",
           "a density of " + format_number(p.density, 4) + " kg/m^3 is beyond what double precision resolves");
  for (int a = 0; a < m.dim; ++a)
    for (int side = 0; side < 2; ++side) {
      const std::string key = std::string("fluid.boundary.") + face_names()[2 * a + side] + "_velocity";
      if (d.has(key)) {
        const auto v = d.reals(key);
        for (int c = 0; c < m.dim && c < static_cast<int>(v.size()); ++c) {
          check_speed(d, key, v[c], p.grid, p.density);
          p.grid.bc[a][side].velocity[c] = v[c];
        }
      }
    }
  if (d.has("fluid.pressure_gradient")) p.pressure_gradient = d.real("fluid.pressure_gradient");
  if (d.has("fluid.bulk_velocity")) {
    p.bulk_velocity = d.real("fluid.bulk_velocity");
    check_speed(d, "fluid.bulk_velocity", p.bulk_velocity, p.grid, p.density);
  }
  p.velocity_scale = d.has("fluid.velocity_scale") ? d.real("fluid.velocity_scale") : default_velocity_scale(p);
  p.length_scale = d.has("fluid.length_scale") ? d.real("fluid.length_scale") : m.box.len[0];
  p.dimensionless = d.has("fluid.reynolds");
  p.viscosity = p.dimensionless ? p.density * p.velocity_scale * p.length_scale / d.real("fluid.reynolds")
                                : d.real("fluid.viscosity");
  // (a viscosity of 1e308 or a density of 1e-310 gave nu = inf, reported as a step to reduce
  // "below 0 s"; a Reynolds number of 1e308 a subnormal nu, and `silt check` printed Re = 2e300)
  if (!std::isnormal(p.length_scale / p.velocity_scale))
    d.fail(d.first_given({"fluid.velocity_scale", "fluid.length_scale"}, "fluid.velocity_scale"),
           "the flow's time L / U = " + format_number(p.length_scale / p.velocity_scale, 4) +
               " s is beyond what double precision resolves");
  if (const double nu = p.nu(); !std::isfinite(nu * p.grid.inv_h2_sum()) || (nu != 0 && !std::isnormal(nu)))
    d.fail(d.first_given({"fluid.reynolds", "fluid.viscosity"}, "fluid.viscosity"),
           "the kinematic viscosity nu = mu / rho = " + format_number(nu, 4) + " m^2/s (its rate on the grid, nu sum " +
               "1/h^2 = " + format_number(nu * p.grid.inv_h2_sum(), 4) +
               " 1/s) is beyond what double precision resolves");
  const double time_unit = p.time_unit();
  p.dt_fixed = d.has("fluid.dt");
  const double h_min = p.grid.h_min();
  // The adaptive step's keys are read for an adaptive step only: beside fluid.dt they would be
  // accepted and do nothing.
  if (!p.dt_fixed) p.cfl_target = d.real("fluid.cfl");
  if (!p.dt_fixed && d.has("fluid.dt_max")) p.dt_max = d.real("fluid.dt_max") * time_unit;
  else
    p.dt_max = p.nu() > 0 ? std::max(h_min * h_min / p.nu(), 0.1 * p.length_scale / p.velocity_scale)
                          : 0.1 * p.length_scale / p.velocity_scale;
  // The first step of an adaptive run: from the target CFL at the velocity scale, or at a faster
  // known speed: the walls' and inflows', the bulk velocity, the initial vortex's (a
  // fluid.velocity_scale below a lid's; a Taylor-Green vortex 3 times faster than its velocity
  // scale took a first step at CFL 1.7 and failed).
  const double first_rate = std::max({m.dim * p.velocity_scale / h_min, known_rate(p), vortex_rate(p)});
  p.dt = p.dt_fixed ? d.real("fluid.dt") * time_unit : std::min(p.dt_max, p.cfl_target / first_rate);
  const std::string viscous = d.string("fluid.viscous");
  p.viscous = viscous == "explicit"         ? Viscous::kExplicit
              : viscous == "backward_euler" ? Viscous::kBackwardEuler
                                            : Viscous::kCrankNicolson;
  if (!p.dt_fixed) p.dt = std::min(p.dt, viscous_dt_limit(p));
  p.stop_when_steady = d.boolean("run.stop_when_steady");
  p.steady_tol = d.real("run.steady_tol");
  // The CG's knobs where there is a CG (read otherwise, they would be accepted and do nothing).
  if (p.projection == Projection::kMultigridCg) {
    p.tolerance = d.real("fluid.tolerance");
    p.max_iterations = static_cast<int>(d.integer("fluid.max_iterations"));
  }
}

void compile_lines(const SceneDesc& d, const Model& m, FluidParams& p) {
  const int n = d.group_count("output.lines");
  for (int l = 0; l < n; ++l) {
    const std::string k = "output.lines[" + std::to_string(l) + "].";
    LineProbe probe;
    probe.name = d.string(k + "name");
    if (probe.name.empty()) d.fail(k + "name", "a line probe needs a name (its key in the summary's \"lines\")");
    probe.field = d.string(k + "field");
    if (probe.field == "w" && m.dim == 2) d.fail(k + "field", "w is the z velocity: a 2D fluid has none");
    const auto from = d.reals(k + "from"), to = d.reals(k + "to");
    if (static_cast<int>(from.size()) != m.dim) d.fail(k + "from", "needs " + std::to_string(m.dim) + " entries");
    if (static_cast<int>(to.size()) != m.dim) d.fail(k + "to", "needs " + std::to_string(m.dim) + " entries");
    for (int a = 0; a < m.dim; ++a) {
      probe.from[a] = from[a];
      probe.to[a] = to[a];
      for (double x : {from[a], to[a]})
        if (x < m.box.lo[a] - 1e-12 * m.box.len[a] || x > m.box.lo[a] + m.box.len[a] * (1 + 1e-12))
          d.fail(k + (x == from[a] ? "from" : "to"), "the probe's ends must be inside the domain");
    }
    if (probe.from == probe.to) d.fail(k + "to", "the probe's ends are the same point: a segment has two");
    probe.points = static_cast<int>(d.integer(k + "points"));
    // (a hundred probes of a million points each passed check, then took 4.7 GB per ten of them
    // as the summary was written after the run, which died of it without a summary)
    int64_t total = probe.points;
    for (const LineProbe& other : p.lines) total += other.points;
    if (total > kMaxLinePoints)
      d.fail(k + "points",
             "the line probes sample " + std::to_string(total) + " points in all, above " +
                 std::to_string(kMaxLinePoints) + " (a summary of about " +
                 format_number(kMaxLinePoints * kSummaryBytesPerPoint / 1e6, 3) + " MB): use fewer; the grid has " +
                 std::to_string(*std::max_element(p.grid.n.begin(), p.grid.n.end())) + " cells along its longest axis");
    for (const LineProbe& other : p.lines)
      if (other.name == probe.name) d.fail(k + "name", "two line probes are named '" + probe.name + "'");
    p.lines.push_back(probe);
  }
}

// A bound on fluid.dt as the scene gives it: in units of L / U in the dimensionless form, rounded
// down and strictly below it (a bound of exactly 1.25 printed as 1.25 was then refused by its
// rounding: "nu dt sum 1/h^2 = 0.6 exceeds 0.6").
std::string scene_step(const Model& m, const FluidParams& p, double seconds) {
  return format_bound_below(seconds / p.time_unit() * (1 - 1e-12), 4) + (p.dimensionless ? " L/U" : m.unit("s"));
}

// The largest fixed step that every stability limit allows (the explicit viscous term's or
// Crank-Nicolson's slowest mode's, and the CFL number of the speeds known before the run), which
// each of their refusals advises (each advised its own bound, which another limit then refused).
double fixed_step_bound(const FluidParams& p) {
  double bound = std::numeric_limits<double>::infinity();
  if (const double rate = p.nu() * p.grid.inv_h2_sum(); p.viscous == Viscous::kExplicit && rate > 0)
    bound = FluidParams::kViscousLimit / rate;
  if (const double rate = slowest_viscous_rate(p); p.viscous == Viscous::kCrankNicolson && rate > 0)
    bound = std::min(bound, FluidParams::kCnModeLimit / rate);
  if (const double rate = known_rate(p); rate > 0) bound = std::min(bound, FluidParams::kCflLimit / rate);
  return bound;
}

// What a fixed step refused by a viscous limit should become: below the bound of every limit at
// once, or the other scheme that takes this step, where one does (each refusal named a scheme
// that was then refused at the same step). A bound below 1e-12 of L / U, which check_tiny_step
// refuses, is not advised.
std::string viscous_step_advice(const Model& m, const FluidParams& p) {
  const double floor = 1e-12 * p.length_scale / p.velocity_scale;
  std::string advice;
  if (const double bound = fixed_step_bound(p); bound > floor)
    advice = "reduce fluid.dt below " + scene_step(m, p, bound);
  for (const Viscous v : {Viscous::kCrankNicolson, Viscous::kBackwardEuler}) {
    FluidParams other = p;
    other.viscous = v;
    if (v == p.viscous || p.dt > fixed_step_bound(other)) continue;
    return advice + (advice.empty() ? "use" : " or use") + " fluid.viscous = \"" +
           (v == Viscous::kCrankNicolson ? "crank_nicolson" : "backward_euler") + "\"";
  }
  if (!advice.empty()) return advice;
  // (backward Euler has no viscous limit: its bound is the CFL number's, which this step passes)
  FluidParams implicit = p;
  implicit.viscous = Viscous::kBackwardEuler;
  const double bound = fixed_step_bound(implicit);
  return std::string("no step above 1e-12 of L / U is stable with this scheme and ") +
         (p.dimensionless ? "fluid.reynolds" : "fluid.viscosity") + ": use fluid.viscous = \"backward_euler\"" +
         (bound > floor ? " with fluid.dt below " + scene_step(m, p, bound) : std::string());
}

}  // namespace

// A step below 1e-12 of the flow's time L / U: the projection divides by it, and far below it
// overflows (a CFL or a Reynolds number of 1e-300 ended in a NaN, whose report then advised a
// smaller step). Named by what set it; before the run length is counted in steps of it.
void check_tiny_step(const SceneDesc& d, const FluidParams& p) {
  if (const double flow_time = p.length_scale / p.velocity_scale; p.dt < 1e-12 * flow_time) {
    const bool viscous = !p.dt_fixed && viscous_dt_limit(p) <= p.dt;
    const bool capped = !p.dt_fixed && !viscous && p.dt_max <= p.dt && d.has("fluid.dt_max");
    const std::string key = p.dt_fixed ? "fluid.dt"
                            : viscous  ? (p.dimensionless ? "fluid.reynolds" : "fluid.viscosity")
                            : capped   ? "fluid.dt_max"
                                       : "fluid.cfl";
    d.fail(key, key + " gives the fluid a step of " + format_number(p.dt, 4) +
                    " s, below 1e-12 of the flow's time L / U = " + format_number(flow_time, 4) + " s" +
                    (viscous ? ": the viscous limit of so viscous a fluid; use fluid.viscous = \"backward_euler\", "
                               "which has none, or a lower viscosity"
                             : ""));
  }
}

std::string fluid_note(const Model& m, double dt) {
  const FluidParams& p = m.params.get<FluidParams>();
  if (!(dt > 0)) return "";
  std::string note;
  auto add = [&note](const std::string& part) { note += (note.empty() ? "" : "; ") + part; };
  // A viscous layer (a boundary layer, L Re^-1/2 thick; the dissipative scale of turbulence is
  // finer still) thinner than a cell: the grid resolves none, and the energy-conserving advection
  // has no dissipation of its own to stand in (Re = 1e12 on 32 cells ran on without a word).
  const double re = p.nu() > 0 ? p.velocity_scale * p.length_scale / p.nu() : HUGE_VAL;
  if (const double layer = p.length_scale / std::sqrt(re); layer < p.grid.h[0])
    add("Re = " + format_number(re, 3) + ": viscous layers about L Re^-1/2 = " + format_number(layer, 3) + m.unit("m") +
        " thick are thinner than a cell (h = " + format_number(p.grid.h[0], 3) + m.unit("m") +
        "), which the grid does not resolve; use more fluid.cells or a lower Reynolds number");
  const double flow_time = p.length_scale / p.velocity_scale, per_flow_time = flow_time / dt;
  if (per_flow_time > kManySteps) {
    const bool viscous = !p.dt_fixed && viscous_dt_limit(p) <= dt * (1 + 1e-12);
    add("a flow time L / U = " + format_number(flow_time, 4) + m.unit("s") + " takes " +
        format_number(per_flow_time, 3) + " fluid steps of " + format_number(dt, 4) + m.unit("s") +
        (viscous ? std::string(", the viscous limit of so viscous a fluid (") +
                       (p.dimensionless ? "fluid.reynolds" : "fluid.viscosity") +
                       "); fluid.viscous = \"backward_euler\" has none"
                 : std::string()));
  }
  // The initial vortex past the CFL limit at a fixed step: a run from it fails at its first step
  // (`check` said ok); from a state restored or steered since, it need not.
  if (const double rate = vortex_rate(p); p.dt_fixed && dt * rate > FluidParams::kCflLimit)
    add("the initial vortex (fluid.initial_velocity) alone gives a CFL number dt sum |U|/h = " +
        format_past(dt * rate, FluidParams::kCflLimit, 6) + " above " + format_number(FluidParams::kCflLimit, 4) +
        " at this fixed step: a run from it fails at its first step; reduce fluid.dt below " +
        scene_step(m, p, FluidParams::kCflLimit / rate));
  // max |u(t + dt) - u(t)| is at least the rounding of u, about 2 eps max |u|: the change rate
  // (per unit time L / U) cannot fall below 2 eps L / (U dt), measured 2.2e-6 at dt = 1e-10 L / U.
  if (const double floor = 2 * std::numeric_limits<double>::epsilon() * per_flow_time;
      p.stop_when_steady && floor > p.steady_tol)
    add("run.steady_tol = " + format_number(p.steady_tol, 3) +
        " is below the rounding of the velocity's change over one step (about " + format_number(floor, 3) +
        " per L / U at this step): the steady stop cannot fire; raise run.steady_tol");
  return note;
}

void compile_fluid(const SceneDesc& d, Model& m) {
  FluidParams& p = m.params.get<FluidParams>();
  for (const char* k : {"run.dt", "run.dt_over_tc"})
    if (d.has(k))
      d.fail(k, "a fluid's step is fluid.dt, or adaptive from fluid.cfl: " + std::string(k) + " does not apply");
  // The grains' DEM step and the fluid's step would share one dt (the CFL's, far beyond a contact
  // time) with neither force felt by the other: refused until the grains are coupled to the grid.
  if (m.n_grains > 0)
    d.fail("fluid.cells",
           "grains and a resolved [fluid] in one scene are not coupled yet (neither would feel the "
           "other); run the fluid alone, or grains in a liquid with [drag] (a drag on each grain) or "
           "[lubrication] (a paste)");
  // A uniform body force on a fluid of one density adds the hydrostatic pressure rho g.x and moves
  // nothing between walls; along a periodic axis it is the drive fluid.pressure_gradient gives.
  // Accepted, it would be listed by `silt check` and do nothing.
  if (const std::string k = d.first_given({"gravity.vector", "gravity.magnitude", "gravity.angle"}, ""); !k.empty())
    d.fail(k,
           "gravity does not act on a fluid alone (it would only add the hydrostatic pressure rho g.x); drive "
           "a flow along a periodic axis with fluid.pressure_gradient, or remove [gravity]");
  compile_grid(d, m, p.grid);
  p.initial = d.string("fluid.initial") == "taylor_green" ? Initial::kTaylorGreen : Initial::kRest;
  if (p.initial == Initial::kTaylorGreen) {
    p.initial_velocity = d.real("fluid.initial_velocity");
    check_speed(d, "fluid.initial_velocity", p.initial_velocity, p.grid, d.real("fluid.density"));
  }
  if (p.initial == Initial::kTaylorGreen)
    for (int a = 0; a < m.dim; ++a)
      if (!m.box.periodic[a]) d.fail("fluid.initial", "the Taylor-Green vortex needs a periodic box");
  if (d.has("fluid.pressure_gradient") || d.has("fluid.bulk_velocity")) {
    const std::string axis = d.string("fluid.drive_axis");
    p.drive_axis = axis[0] - 'x';
    const std::string key = d.has("fluid.pressure_gradient") ? "fluid.pressure_gradient" : "fluid.bulk_velocity";
    p.drive = d.has("fluid.pressure_gradient") ? Drive::kPressure : Drive::kFlowRate;
    if (p.drive_axis >= m.dim) d.fail("fluid.drive_axis", "a " + std::to_string(m.dim) + "D scene has no axis " + axis);
    // (blamed on the driver with the axis named, where the axis is the default; it said the axis
    // was periodic, at the driver's line, for a drive_axis given along walls)
    if (!m.box.periodic[p.drive_axis])
      d.fail(d.has("fluid.drive_axis") ? "fluid.drive_axis" : key,
             "a flow is driven only along a periodic axis, and " + axis + " is not periodic (" +
                 (d.has("fluid.drive_axis") ? "" : "fluid.drive_axis = " + axis + "; ") + "domain.periodic)");
  }
  p.projection = d.string("fluid.projection") == "multigrid_cg" ? Projection::kMultigridCg : Projection::kFft;
  compile_steerable(d, m, p);
  check_tiny_step(d, p);
  compile_lines(d, m, p);
  m.cells = p.grid.n;
  if (m.dim == 2) m.cells[2] = 1;
  // The fluid's step is the step's (the grains, if any, sub-cycle in a later version).
  m.propose_dt(p.dt);
  m.adaptive_dt = m.adaptive_dt || !p.dt_fixed;
  m.dt_key = p.dt_fixed ? "fluid.dt" : "fluid.cfl";
  m.stop_when_steady = p.stop_when_steady;
}

void finish_fluid(const SceneDesc& d, Model& m) {
  const FluidParams& p = m.params.get<FluidParams>();
  const double inv = p.grid.inv_h2_sum();
  if (p.dt_fixed && p.viscous == Viscous::kExplicit && p.nu() * p.dt * inv > FluidParams::kViscousLimit)
    d.fail("fluid.dt", "the explicit viscous term is unstable: nu dt sum 1/h^2 = " +
                           format_past(p.nu() * p.dt * inv, FluidParams::kViscousLimit, 4) + " exceeds " +
                           format_number(FluidParams::kViscousLimit, 4) + "; " + viscous_step_advice(m, p));
  const double mode = p.dt * slowest_viscous_rate(p);
  if (p.dt_fixed && p.viscous == Viscous::kCrankNicolson && mode > FluidParams::kCnModeLimit)
    d.fail("fluid.dt", "Crank-Nicolson damps the box's slowest viscous mode too little at this step: nu dt k^2 = " +
                           format_past(mode, FluidParams::kCnModeLimit, 4) + " exceeds " +
                           format_number(FluidParams::kCnModeLimit, 4) +
                           " (beyond 3.75 it turns over instead of decaying); " + viscous_step_advice(m, p));
  // The walls' and inflows' speeds and an imposed bulk velocity bound the first steps' CFL number
  // from below, from any state (the fluid may only add to it): a fixed step past the limit with
  // them fails in its first two steps. (`check` said ok to a channel whose bulk velocity gave 6.4
  // at the limit 1.6.) The initial vortex's is a note (fluid_note): a state restored or kept
  // through a change is not it.
  std::string what;
  if (const double rate = known_rate(p, &what); p.dt_fixed && p.dt * rate > FluidParams::kCflLimit)
    d.fail("fluid.dt",
           what + " a CFL number dt sum |U|/h = " + format_past(p.dt * rate, FluidParams::kCflLimit, 6) + " above " +
               format_number(FluidParams::kCflLimit, 4) +
               ", the stability limit of RK3 advection; reduce fluid.dt below " +
               scene_step(m, p, fixed_step_bound(p)) +
               " at least (the flow they drive adds to it), or give fluid.cfl instead of it for the adaptive step");
  const double need = estimated_memory_bytes(m), have = available_memory_bytes();
  if (need > 0.9 * have)
    d.fail("fluid.cells", "the fluid needs about " + format_number(need / (1 << 30), 3) + " GiB (" +
                              format_number(static_cast<double>(p.grid.cells()), 4) + " cells); the machine has " +
                              format_number(have / (1 << 30), 3) + " GiB available: use fewer cells (" +
                              fitting_cells(m, p.grid, need, 0.8 * have) + ")");
}

}  // namespace silt::fluid
