// The parameters of a resolved fluid (Izard 2014 sec. 2.2), compiled from the [fluid] table of a
// scene by the fluid module (fluid/module.cpp).
#pragma once

#include <string>
#include <vector>

#include "fluid/grid.hpp"

namespace silt::fluid {

// How the viscous term is advanced: explicitly with the advection (RK3), or implicitly in each
// substep, by Crank-Nicolson (second order; damps the fastest modes little) or backward Euler
// (first order; damps every mode, as the exact decay does).
enum class Viscous : uint8_t { kExplicit, kCrankNicolson, kBackwardEuler };
// How the pressure Poisson equation is solved: fast transforms (FFTW), or CG preconditioned by a
// multigrid V-cycle (the reference).
enum class Projection : uint8_t { kFft, kMultigridCg };
// How the flow through a periodic direction is driven.
enum class Drive : uint8_t { kNone, kPressure, kFlowRate };
enum class Initial : uint8_t { kRest, kTaylorGreen };

// A line probe ([[output.lines]]): a field sampled at `points` points along a segment at the end
// of the run.
// All probes together, and what a point costs as the summary is written after the run: about
// 125 bytes of its text and 420 of memory while it is built in 2D, 140 and 520 in 3D (measured
// with one probe of 1e6 points: 125 and 140 MB, peaks 412 and 522 MB above the run's).
constexpr int64_t kMaxLinePoints = 1'000'000;
constexpr double kSummaryBytesPerPoint = 140;
constexpr double summary_memory_per_point(int dim) { return dim == 3 ? 520 : 420; }

struct LineProbe {
  std::string name, field;  // field: u, v, w, p, vorticity
  std::array<double, 3> from{0, 0, 0}, to{0, 0, 0};
  int points = 0;
};

struct FluidParams {
  Grid grid;
  double density = 1;    // rho [kg/m^3]
  double viscosity = 0;  // mu [Pa s] (steerable); nu = mu / rho
  double nu() const { return viscosity / density; }
  Viscous viscous = Viscous::kCrankNicolson;
  Projection projection = Projection::kFft;
  double tolerance = 1e-10;  // multigrid_cg: relative residual
  int max_iterations = 200;
  // Time step: fixed (dt > 0), or adaptive from the target CFL number (dt_fixed = false).
  bool dt_fixed = false;
  double dt = 0;                                // [s] the fixed step, or the first adaptive one
  double cfl_target = 0.5;                      // adaptive step: dt sum_a max|u_a| / h_a at most this (steerable)
  double dt_max = 0;                            // adaptive step at most this [s]
  static constexpr double kCflLimit = 1.6;      // RK3 on the imaginary axis: sqrt(3) = 1.73
  static constexpr double kViscousLimit = 0.6;  // RK3 on the real axis: nu dt sum 1/h^2 <= 2.51 / 4
  // Crank-Nicolson: nu dt k^2 at most this for the box's longest wavelength (slowest_viscous_rate).
  // Each substep multiplies a mode by (1 - z/2) / (1 + z/2), z = alpha_k dt nu k^2, which tends to
  // -1 as z grows: a step of nu dt k^2 = 1 decays the mode by 0.362 against exp(-1) = 0.368, one
  // of 3.75 turns it over in its first substep, and one of 1e6 leaves it as it was, its sign
  // flipped three times (a Taylor-Green vortex at Re = 1e-12 kept its kinetic energy).
  static constexpr double kCnModeLimit = 1.0;
  // Dimensionless form: velocity and length scales (Re = U L / nu, times in L / U).
  double velocity_scale = 1, length_scale = 1;
  bool dimensionless = false;
  // The unit of the scene's times (fluid.dt, fluid.dt_max) in seconds: L / U in the dimensionless form.
  double time_unit() const { return dimensionless ? length_scale / velocity_scale : 1.0; }
  Drive drive = Drive::kNone;
  int drive_axis = 0;
  double pressure_gradient = 0;  // kPressure: -dp/dx along drive_axis [Pa/m] (steerable)
  double bulk_velocity = 0;      // kFlowRate: the imposed mean velocity along drive_axis [m/s] (steerable)
  // run.stop_when_steady: runs end when the velocity's relative change per unit time L / U falls
  // below steady_tol (fluid/step.hpp, kChangeRate).
  bool stop_when_steady = false;
  double steady_tol = 1e-6;
  Initial initial = Initial::kRest;
  double initial_velocity = 0;  // Taylor-Green amplitude U0 [m/s]
  std::vector<LineProbe> lines;
};

}  // namespace silt::fluid
