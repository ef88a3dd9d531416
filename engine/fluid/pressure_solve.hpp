// The linear solves of the fluid step: the pressure Poisson equation of the projection, by fast
// transforms (fluid/fast_solver.hpp) or by CG with a multigrid V-cycle (fluid/multigrid.hpp), and
// the Helmholtz equations of the implicit viscous term, by fast transforms.
#pragma once

#include <memory>

#include "fluid/fast_solver.hpp"
#include "fluid/step.hpp"
#include "silt/linalg.hpp"

namespace silt::fluid {

// The transform kind of each axis for the pressure (cell centres), and for the unknowns of
// velocity component a (its updated faces).
std::array<SolverAxis, 3> pressure_axes(const Grid& g);
std::array<SolverAxis, 3> velocity_axes(const Grid& g, int a);

void make_pressure_solver(const FluidParams& p, FluidWorkspace& w);
std::unique_ptr<FastSolver> make_helmholtz_solver(const Grid& g, int a);
// Solves Lap phi = -w.cells (w.cells holds -div u* / (alpha dt)) into w.phi (padded, ghosts not
// filled); the report of the CG, or of the transforms (0 iterations, the residual not computed).
linalg::SolveReport solve_pressure(const FluidParams& p, FluidWorkspace& w);
size_t pressure_solver_bytes(const FluidWorkspace& w);

}  // namespace silt::fluid
