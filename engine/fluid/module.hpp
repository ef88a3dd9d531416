// The fluid module's parts (fluid/module.cpp assembles them into its ModuleSpec).
#pragma once

#include <array>
#include <string_view>
#include <vector>

#include "fluid/params.hpp"
#include "silt/grid_field.hpp"
#include "silt/model.hpp"
#include "silt/module.hpp"
#include "silt/state.hpp"

namespace silt::fluid {

const std::array<const char*, 6>& face_names();  // x_lo, x_hi, ...
std::vector<KeySpec> fluid_keys();
std::vector<ObservableSpec> fluid_observables();
void compile_fluid(const SceneDesc& d, Model& m);
void finish_fluid(const SceneDesc& d, Model& m);
std::string describe_fluid(const Model& m);
std::string steer_fluid(Model& m, const Model& fresh);
// At a step of dt: that the grid resolves no viscous layer (L Re^-1/2 below a cell), that a flow
// time L / U takes more than kManySteps steps, and that the steady stop cannot fire as the
// rounding of the velocity's change over one step exceeds run.steady_tol; "" when none (said by
// `silt check` and at the start of a run).
inline constexpr double kManySteps = 1e6;
std::string fluid_note(const Model& m, double dt);

// Measurements of the velocity field of a state (fluid/measure.cpp).
double kinetic_energy(const FluidParams& p, const State& s);  // (rho / 2) integral |u|^2 [J, J/m in 2D]
// The mean of velocity component a over the domain [m/s]: its faces weighted as kinetic_energy's.
double mean_velocity(const FluidParams& p, const State& s, int a);
double enstrophy(const FluidParams& p, const State& s);       // (1/2) integral |omega|^2 [m^3/s^2, m^2/s^2 in 2D]
double max_divergence(const FluidParams& p, const State& s);  // max |div u| [1/s]
// The velocity (3 components), pressure and vorticity (1 component in 2D, 3 in 3D) at the cell
// centres.
std::vector<GridField> cell_fields(const FluidParams& p, const State& s, std::string_view only = {});
// Field `field` (u, v, w, p, vorticity) at point x, interpolated (linearly) from its own
// locations, boundary values included.
double sample(const FluidParams& p, const State& s, const std::string& field, const std::array<double, 3>& x);
std::vector<LineSample> line_samples(const Model& m, const State& s);

}  // namespace silt::fluid
