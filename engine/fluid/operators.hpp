// The drivers that sweep the kernels of fluid/stencil_kernels.hpp over the grid, in parallel over
// rows of x (each value written by one thread: the results do not depend on the thread count).
// A sweep that updates several arrays (the components, the pressure) does all of them in one
// pass over the grid, and its loops run in AVX2 where the processor has it, with the same bits
// as the baseline (core/simd_level.hpp). Velocities are padded arrays (fluid/layout.hpp) whose
// ghosts are filled.
#pragma once

#include <array>
#include <vector>

#include "fluid/fast_solver.hpp"
#include "fluid/grid.hpp"
#include "fluid/layout.hpp"
#include "fluid/params.hpp"

namespace silt::fluid {

using Padded = std::array<double*, 3>;
using PaddedConst = std::array<const double*, 3>;

// One Runge-Kutta substep of the momentum equation, on the faces each component updates
// (update_range), in one sweep:
//   N = advection of u_a + nu Lap u_a + force[a]                 (nu = 0: no explicit viscosity)
//   u*_a = u_a + gdt N + zdt n_prev_a - adt grad_a p + beta (Lap u_a + bc_lap_a)   (Crank-Nicolson)
//   u*_a = u_a + gdt N + zdt n_prev_a - adt grad_a p + beta bc_lap_a                (backward Euler)
//                                                                 (p: the pressure / rho so far,
//                                                                  ghosts filled; beta: the
//                                                                  implicit solve's coefficient,
//                                                                  bc_lap its boundary values)
//   n_prev_a = N                                                  (for the next substep)
struct SubstepCoefficients {
  Viscous viscous = Viscous::kExplicit;
  double nu = 0, gdt = 0, zdt = 0, adt = 0, beta = 0;
  const double* p = nullptr;  // padded
  std::array<double, 3> force{0, 0, 0};
};
void momentum_substep(const Grid& g, const Layout& L, const PaddedConst& u, const Padded& u_star, const Padded& n_prev,
                      const PaddedConst& bc_lap, const SubstepCoefficients& c);
// out_a = Lap u_a on the updated faces.
void component_laplacian(const Grid& g, const Layout& L, int a, const double* u, double* out);
// cells[c] = scale * div u in every cell (unpadded, x fastest).
void divergence(const Grid& g, const Layout& L, const PaddedConst& u, double* cells, double scale);
// cells[c] = div u, and the largest |div u| (infinite if one is NaN).
double divergence_max(const Grid& g, const Layout& L, const PaddedConst& u, double* cells);
// The projection's update, in one sweep: u_a -= coeff * grad_a phi on the updated faces, and
// p += phi in the cells (padded; its ghosts left as they were).
void project_velocity(const Grid& g, const Layout& L, const Padded& u, const double* phi, double coeff, double* p);
// Copies between a padded array and the unknowns of component a (its updated faces, x fastest),
// or the cells (a = -1).
void gather_unknowns(const Grid& g, const Layout& L, int a, const double* padded, double* out);
void scatter_unknowns(const Grid& g, const Layout& L, int a, const double* in, double* padded);
// The same unknowns as rows of the padded array, for a fast solve that reads and writes them there.
SolveRows unknown_rows(const Grid& g, const Layout& L, int a, double* padded);
// Number of the unknowns of component a (a = -1: cells), per axis.
std::array<int64_t, 3> unknown_dims(const Grid& g, int a);

}  // namespace silt::fluid
