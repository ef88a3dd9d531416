// Ghost values from the boundary conditions of each face of the box (fluid/grid.hpp), so that the
// stencils of fluid/stencil_kernels.hpp read the right values next to a wall, a lid, an inflow or
// an outflow, or across a periodic face.
#pragma once

#include <array>

#include "fluid/grid.hpp"
#include "fluid/layout.hpp"

namespace silt::fluid {

// The ghosts of every velocity component (and the given normal velocity on wall and inflow
// faces; along a periodic axis, the face n copied from face 0). Axes are filled in order, each
// over the whole padded extent of the others, so edges and corners are filled too.
//   normal component on a wall: 0 on the face; inflow: the inflow's; outflow: zero gradient.
//   tangential component: no-slip wall at velocity U_w: ghost = 2 U_w - u (the mean is U_w on
//   the face); free-slip and outflow: ghost = u (zero gradient); inflow: 2 U_in - u.
void fill_velocity_ghosts(const Grid& g, const Layout& L, const std::array<double*, 3>& c);

// The ghosts of a cell-centred scalar under the pressure's conditions: periodic; Neumann
// (ghost = value); Dirichlet, zero on the face (ghost = -value).
void fill_pressure_ghosts(const Grid& g, const Layout& L, double* p);

// Inflow velocity component `a` at a point of the face (axis b, side) whose position is x: the
// peak value times 4 xi (1 - xi) for each other non-periodic axis when parabolic.
double inflow_velocity(const Grid& g, int b, int side, int a, const std::array<double, 3>& x);

}  // namespace silt::fluid
