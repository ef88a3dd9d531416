// The grains' stress (Peyneau 2009 eq. 1.4 with the kinetic term of eq. 3.11), compression
// positive: Omega sigma = sum_i m_i v_i (x) v_i + sum_contacts f_ij (x) d_ij, with f_ij the force on
// i from j and d_ij = x_i - x_j (nearest image); for a repulsive contact both point the same way.
// v is the velocity relative to the affine flow of a deforming box, so the kinetic part is that
// of the fluctuations. Grain-wall contacts are not in it (walls are outside the averaging volume).
#pragma once

#include <array>

#include "silt/state.hpp"

namespace silt::dem {

// Omega sigma, component (a, b) at [3 a + b], summed over fixed chunks of grains in order (each
// grain's kinetic term, then its row of pairs), so that it does not depend on the number of
// threads. Full: every component; otherwise only the diagonal and xy (what a controlled box
// needs), the others left zero.
template <bool Full>
std::array<double, 9> virial_sums(const State& s);
// Every component of sum over listed pairs f_ij (x) d_ij for another per-pair force array of the
// layout of pair_f (P*D, force on i from j): a lubrication force; no kinetic term.
std::array<double, 9> pair_virial_sums(const State& s, const double* pair_force);

}  // namespace silt::dem
