// The resistance matrix of a lubricated paste, Peyneau (2009) sec. 2.2: Xi = G^T xi G (eq.
// 2.42-2.47), over the unknowns (V_1, omega_1, ..., V_N, omega_N, epsdot_1 ... epsdot_d): every
// grain's velocity relative to the affine flow of the box and its angular velocity (1 in 2D, 3 in
// 3D), then the box's diagonal strain rates (epsdot_a > 0 is expansion). G maps them to each
// connection's relative velocity at contact, eq. 2.21 written for any dimension,
//   V_ij = (V_i - V_j) + (R_i omega_i + R_j omega_j) x n_ij - epsdot . r_ij,
// split into its normal part (one row) and its tangential parts (one row in 2D, two in 3D); xi is
// diagonal, xi_N on the normal rows and xi_T on the tangential ones. Then F = -Xi V is every
// grain's lubrication force and torque, and the box rows are the lubrication stress times the
// box volume, A sigma^lub_aa = sum over connections of F_(j<-i),a r_ij,a (eq. 2.31).
//
// Xi is symmetric positive semi-definite: <V, Xi V> = <G V, xi G V> >= 0. Its kernel holds the
// uniform translations, and every grain (or cluster) with no connection to the rest adds more:
// connected_components() finds them before a factorisation is attempted. Connectivity is not
// enough, though (the thesis's sec. 2.2.3 reads as if it were): a connection graph without an odd
// cycle (a tree, a square lattice) lets the grains counter-rotate as gears with nothing sliding,
// another kernel vector; random dense packings have triangles.
#pragma once

#include <cstdint>
#include <vector>

#include "silt/linalg.hpp"

namespace silt::paste {

struct Connection {
  int32_t i = 0, j = 0;
  double n[3] = {0, 0, 0};    // unit vector from i to j
  double r[3] = {0, 0, 0};    // r_j - r_i (nearest periodic image)
  double xi_n = 0, xi_t = 0;  // lubrication resistances [N s/m]
  // In contact with implicit contacts (paste/contact_stiffness.hpp): dt times the contact's normal
  // stiffness, and its tangential one while it sticks [N s/m]; 0 otherwise.
  double k_n = 0, k_t = 0;
};

struct ResistanceLayout {
  int dim = 2;
  int64_t grains = 0;
  bool box = false;  // the d strain-rate unknowns at the end
  int rot() const { return dim == 2 ? 1 : 3; }
  int per_grain() const { return dim + rot(); }
  int64_t size() const { return grains * per_grain() + (box ? dim : 0); }
  int64_t velocity(int64_t g) const { return g * per_grain(); }    // V_g, dim entries
  int64_t spin(int64_t g) const { return g * per_grain() + dim; }  // omega_g, rot() entries
  int64_t strain_rate(int a) const { return grains * per_grain() + a; }
};

// Two unit vectors completing n to an orthonormal basis (3D), or the one of the plane (2D:
// t = e_z x n, Peyneau's t_ij): the directions of a connection's tangential rows.
void tangents(int dim, const double* n, double t[2][3]);

// G, one row per normal and tangential direction of every connection (rows 2 k .. in 2D, 3 k ..
// in 3D), radii by grain.
linalg::SparseMatrix connection_map(const ResistanceLayout& layout, const std::vector<Connection>& c,
                                    const std::vector<double>& radius);
// Xi = G^T xi G.
linalg::SparseMatrix resistance_matrix(const ResistanceLayout& layout, const std::vector<Connection>& c,
                                       const std::vector<double>& radius);

// The connected components of the connection graph, as a component index per grain; `count` is
// set to their number. One component: Xi is singular only by the uniform translations.
std::vector<int32_t> connected_components(int64_t grains, const std::vector<Connection>& c, int32_t& count);

}  // namespace silt::paste
