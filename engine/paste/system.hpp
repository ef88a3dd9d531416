// The linear system of a lubricated paste, assembled from the connections of one configuration:
// Xi = G^T xi G (Peyneau 2009 eq. 2.42-2.47, the per-connection algebra of paste/resistance.hpp)
// over the unknowns of SystemLayout, stored as one sparse matrix whose pattern, and where each
// connection's blocks are in it, are kept while the connected pairs stay the same.
//
// How the shear enters (the thesis does not say): the grains' velocities V are relative to the
// affine flow of the box, u = epsdot . (x - lo) + gammadot (y - lo_y) e_x. The strain rates of
// the controlled box lengths are unknowns (the imposed stresses are their equations); the shear
// rate is imposed, so its column of G^T xi G is moved to the right-hand side: the lubrication
// force of the affine shear on each grain, -Xi_(., gammadot) gammadot, drives the solve. The
// force on i from j then resists the relative velocity at contact of eq. 2.21 with the shear's
// term -gammadot r_ij,y e_x added to -epsdot . r_ij.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "paste/lubrication_laws.hpp"
#include "paste/resistance.hpp"
#include "silt/linalg.hpp"
#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::paste {

struct SystemLayout {
  int dim = 2, rot = 1, per_grain = 3;
  int64_t grains = 0;
  int n_box = 0;                // box strain rates among the unknowns
  int box_axis[3] = {0, 0, 0};  // their axes
  bool shear = false;           // an imposed shear rate (its column goes to the right-hand side)
  int64_t size() const { return grains * per_grain + n_box; }
  int64_t box_unknown(int k) const { return grains * per_grain + k; }
};
SystemLayout make_layout(int dim, int64_t grains, const bool* controlled_axes, bool shear);
// The layout of a model's paste of `grains` grains: its controlled box lengths and its shear.
SystemLayout make_layout(const Model& m, int64_t grains);

// Every listed pair whose gap is at most law.h_max, in the order of the pair list, and the index
// of its pair (for the per-pair force arrays).
struct Links {
  std::vector<Connection> c;
  std::vector<int32_t> pair;
};
void find_connections(const State& s, const LubricationLaw& law, Links& out);

class ResistanceSystem {
 public:
  // Xi of these connections, and shear_rhs() = -Xi_(., gammadot) gammadot. Every grain's
  // diagonal entries are in the pattern, connected or not. Returns whether the pattern changed.
  bool assemble(const SystemLayout& layout, const std::vector<Connection>& c, const std::vector<double>& radius,
                double shear_rate);
  // Add, after assemble, G^T diag(k_n, k_t) G of every connection with a contact stiffness
  // (Connection::k_n, k_t), and its shear column's drive to `rhs`.
  void add_contact_stiffness(const std::vector<Connection>& c, const std::vector<double>& radius, double shear_rate,
                             linalg::Vector& rhs);
  linalg::SparseMatrix& matrix() { return a_; }
  const linalg::SparseMatrix& matrix() const { return a_; }
  const linalg::Vector& shear_rhs() const { return shear_rhs_; }
  // Position in matrix().valuePtr() of diagonal entry k.
  int64_t diagonal_position(int64_t k) const { return diag_pos_[k]; }
  // Replace unknown k's row and column by the identity times `scale`, and its right-hand side
  // entry by 0: the unknown is held at zero (a pinned translation, a grain with no connection).
  void pin(int64_t k, double scale, linalg::Vector& rhs);
  void forget() { pairs_.clear(); }
  // The matrix as it is now (pins and diagonal terms included) without the blocks that couple
  // the two grains of every connection whose `keep` is 0: each such connection keeps only its
  // diagonal blocks, half its resistance or more along any motion (for a positive semi-definite
  // [[A, B], [B^T, C]], diag(A, C) >= it / 2). A cheap matrix to factorise as a preconditioner:
  // only the stiff connections fill the factor in. `own_rotations`: also without any entry that
  // couples a grain's rotation to a translation, to the box or to another grain's rotation, so
  // that each grain's rotation keeps only its own diagonal block: the translations' factor is a
  // quarter of the whole one in 3D (3 unknowns a grain instead of 6), the rotations' blocks add
  // no fill, and the matrix stays positive definite (a block diagonal of principal submatrices).
  linalg::SparseMatrix sparsified(const std::vector<uint8_t>& keep, bool own_rotations) const;
  size_t bytes() const;

 private:
  SystemLayout layout_;
  linalg::SparseMatrix a_;
  linalg::Vector shear_rhs_;
  std::vector<std::pair<int32_t, int32_t>> pairs_;  // the connected pairs of the pattern
  // Per connection, where its grains' blocks are in their columns (build_pattern).
  std::vector<std::array<int32_t, 4>> slots_;
  int64_t connected_ = 0;  // grains with a connection
  std::vector<int32_t> diag_pos_;
  // build_pattern's work arrays, kept: the pattern changes at nearly every step of a large
  // system, and fresh arrays would cost a page fault per page each time.
  std::vector<int64_t> start_, rank_, partners_;
  std::vector<int32_t> adj_;
  // The connections of each grain in their order: by_grain_[by_grain_start_[g] ..
  // by_grain_start_[g + 1]) (the assembly's columns, grain by grain).
  std::vector<int32_t> by_grain_start_, by_grain_;
  std::vector<double> local_;  // per connection, its local G^T xi G
  void build_pattern(const std::vector<Connection>& c);
  // Add a connection's local block into the matrix (its grains' slots from build_pattern), its
  // shear column times -shear_rate to rhs.
  void add_block(const Connection& c, const double* local, const std::array<int32_t, 4>& slot, double shear_rate,
                 linalg::Vector& rhs);
  // add_block of every connection's local_ block in their order into the matrix and shear_rhs_,
  // the same sums, in parallel by grain.
  void add_blocks(const std::vector<Connection>& cs, double shear_rate);
};

// The local unknowns of a connection: grain i's, grain j's, the box strain rates, then the shear
// rate: 2 p + n_box (+ 1) of them.
int local_size(const SystemLayout& layout);
// Global index of local unknown q of connection c (-1 for the imposed shear rate).
int64_t local_to_global(const SystemLayout& layout, const Connection& c, int q);
// The connection's rows of G over its local unknowns (dim rows of local_size entries).
void local_map(const SystemLayout& layout, const Connection& c, double ri, double rj, double* g);
// G^T diag(normal, tangential...) G of a connection over its local unknowns (n x n, symmetric).
void local_block(const SystemLayout& layout, const Connection& c, double ri, double rj, double normal,
                 double tangential, double* out);
// W, for a linalg::CoarseCorrection: the rows of G (one column each over the unknowns, the imposed
// shear's entry left out) along which a connection resists more than `ratio` times its tangential
// lubrication xi_T: the normal of a near-contact or a contact (xi_N + k_N), and with implicit
// contacts the tangents of a sticking one (xi_T + k_T). These are the directions that turn with
// the grains and take an older factor furthest from the matrix. Each column keyed by its
// connection and direction (direction_key), so that E is ordered from the last solve's order.
linalg::CoarseSpace stiff_directions(const SystemLayout& layout, const std::vector<Connection>& c,
                                     const std::vector<double>& radius, double ratio);
// The key of direction d (0 the normal, 1 and 2 the tangents) of the connection of grains i and j
// among n: 3 (lo n + hi) + d, lo and hi the smaller and larger id.
inline int64_t direction_key(int64_t n, int64_t i, int64_t j, int d) {
  return 3 * (std::min(i, j) * n + std::max(i, j)) + d;
}
// The force on i from j of a connection (dim components) for local unknowns u (eq. 2.24): its
// lubrication, -xi G u; and where `contact` is given, its implicit contact's increment over the
// step, -dt K G u (Connection::k_n, k_t), which the solve counted in the same way.
void connection_force(const SystemLayout& layout, const Connection& c, double ri, double rj, const double* u,
                      double* force, double* contact = nullptr);
// The same with the connection's rows of G (local_map) and its tangents given: for a caller that
// applies it to several sets of unknowns.
void connection_force_with(const SystemLayout& layout, const Connection& c, const double* g, const double tan[2][3],
                           const double* u, double* force, double* contact = nullptr);

}  // namespace silt::paste
