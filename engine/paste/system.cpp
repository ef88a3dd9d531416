#include "paste/system.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "core/parallel.hpp"
#include "dem/contact_laws.hpp"
#include "silt/periodic_image.hpp"

namespace silt::paste {

SystemLayout make_layout(int dim, int64_t grains, const bool* controlled_axes, bool shear) {
  SystemLayout l;
  l.dim = dim;
  l.rot = dim == 2 ? 1 : 3;
  l.per_grain = dim + l.rot;
  l.grains = grains;
  for (int a = 0; a < dim; ++a)
    if (controlled_axes && controlled_axes[a]) l.box_axis[l.n_box++] = a;
  l.shear = shear;
  return l;
}

int local_size(const SystemLayout& l) { return 2 * l.per_grain + l.n_box + (l.shear ? 1 : 0); }

int64_t local_to_global(const SystemLayout& l, const Connection& c, int q) {
  const int p = l.per_grain;
  if (q < p) return c.i * int64_t{p} + q;
  if (q < 2 * p) return c.j * int64_t{p} + (q - p);
  if (q < 2 * p + l.n_box) return l.box_unknown(q - 2 * p);
  return -1;
}

void local_map(const SystemLayout& l, const Connection& c, double ri, double rj, double* g) {
  const int d = l.dim, p = l.per_grain, n = local_size(l);
  double tan[2][3];
  tangents(d, c.n, tan);
  for (int row = 0; row < d; ++row) {
    double* gr = g + row * n;
    std::fill(gr, gr + n, 0.0);
    const double* e = row == 0 ? c.n : tan[row - 1];
    // (V_i - V_j) . e
    for (int a = 0; a < d; ++a) {
      gr[a] = e[a];
      gr[p + a] = -e[a];
    }
    // ((R_i w_i + R_j w_j) x n) . e = (R_i w_i + R_j w_j) . (n x e)
    if (d == 2) {
      const double nxe = c.n[0] * e[1] - c.n[1] * e[0];
      gr[2] = ri * nxe;
      gr[p + 2] = rj * nxe;
    } else {
      const double nxe[3] = {c.n[1] * e[2] - c.n[2] * e[1], c.n[2] * e[0] - c.n[0] * e[2],
                             c.n[0] * e[1] - c.n[1] * e[0]};
      for (int a = 0; a < 3; ++a) {
        gr[3 + a] = ri * nxe[a];
        gr[p + 3 + a] = rj * nxe[a];
      }
    }
    // The affine flow: -epsdot . r_ij on the controlled axes, -gammadot r_ij,y e_x.
    for (int k = 0; k < l.n_box; ++k) gr[2 * p + k] = -e[l.box_axis[k]] * c.r[l.box_axis[k]];
    if (l.shear) gr[n - 1] = -e[0] * c.r[1];
  }
}

void local_block(const SystemLayout& l, const Connection& c, double ri, double rj, double normal, double tangential,
                 double* out) {
  const int d = l.dim, n = local_size(l);
  double g[3 * 16];
  local_map(l, c, ri, rj, g);
  // Each entry once and mirrored: the matrix is symmetric to the bit.
  for (int r = 0; r < n; ++r)
    for (int q = r; q < n; ++q) {
      double v = 0;
      for (int row = 0; row < d; ++row) v += g[row * n + r] * (row == 0 ? normal : tangential) * g[row * n + q];
      out[r * n + q] = v;
      out[q * n + r] = v;
    }
}

SystemLayout make_layout(const Model& m, int64_t grains) {
  bool controlled[3] = {false, false, false};
  if (m.box_control.on)
    for (int a = 0; a < m.dim; ++a) controlled[a] = m.box_control.controlled[a];
  return make_layout(m.dim, grains, controlled, m.shear.on);
}

void connection_force(const SystemLayout& l, const Connection& c, double ri, double rj, const double* u, double* force,
                      double* contact) {
  double g[3 * 16];
  local_map(l, c, ri, rj, g);
  double tan[2][3];
  tangents(l.dim, c.n, tan);
  connection_force_with(l, c, g, tan, u, force, contact);
}

void connection_force_with(const SystemLayout& l, const Connection& c, const double* g, const double tan[2][3],
                           const double* u, double* force, double* contact) {
  const int d = l.dim, n = local_size(l);
  for (int a = 0; a < d; ++a) force[a] = 0;
  if (contact)
    for (int a = 0; a < d; ++a) contact[a] = 0;
  for (int row = 0; row < d; ++row) {
    double v = 0;
    for (int q = 0; q < n; ++q) v += g[row * n + q] * u[q];
    const double* e = row == 0 ? c.n : tan[row - 1];
    const double f = -(row == 0 ? c.xi_n : c.xi_t) * v;
    for (int a = 0; a < d; ++a) force[a] += f * e[a];
    if (!contact) continue;
    const double k = -(row == 0 ? c.k_n : c.k_t) * v;
    for (int a = 0; a < d; ++a) contact[a] += k * e[a];
  }
}

void find_connections(const State& s, const LubricationLaw& law, Links& out) {
  out.c.clear();
  out.pair.clear();
  const int D = s.dim;
  auto scan = [&]<int Dim>() {
    const PeriodicImage<Dim> img(s.box);
    for (int64_t i = 0; i < s.n; ++i)
      for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
        const int32_t j = s.pair_j[p];
        Vec<Dim> r = at<Dim>(s.particle_x.data(), j) - at<Dim>(s.particle_x.data(), i);
        img.apply(r);
        const double dist = r.norm();
        const double ri = s.particle_r[i], rj = s.particle_r[j];
        const double h = dist - ri - rj;
        if (h > law.h_max || !(dist > 0)) continue;
        Connection c;
        c.i = static_cast<int32_t>(i);
        c.j = j;
        for (int a = 0; a < Dim; ++a) {
          c.r[a] = r[a];
          c.n[a] = r[a] / dist;
        }
        // 2 / R_eq = 1 / R_i + 1 / R_j (R for two grains of radius R), as the thesis and the DEM's
        // contacts have it: R_i R_j / (R_i + R_j) made every resistance 4 times too weak normally.
        const double r_eq = dem::reduced_radius(ri, rj);
        c.xi_n = xi_normal(h, r_eq, law);
        c.xi_t = xi_tangential(h, r_eq, law);
        out.c.push_back(c);
        out.pair.push_back(p);
      }
  };
  if (D == 2) scan.template operator()<2>();
  else scan.template operator()<3>();
}

namespace {

// Where the p rows of a grain at `slot` of grain g's partners start in column a of g (the layout
// build_pattern writes: a grain's column holds p rows for each partner in order, then the box's).
inline int64_t grain_block(const int* outer, int p, int64_t g, int a, int64_t slot) {
  return outer[g * p + a] + slot * p;
}

}  // namespace

// The pattern written column by column, its rows in order, without a list of triplets to sort
// (whose allocation and sort cost more than the assembly itself once the connections change at
// every step). Every unknown has its diagonal entry; a connection of i and j fills the p x p
// blocks (i, i), (i, j), (j, i), (j, j), the blocks of i and j against the box strain rates, and
// the strain rates' own block. A grain's column thus holds, for each grain connected to it or
// itself (in order), p rows, then the strain rates' rows; a strain rate's column, p rows for each
// connected grain, then the strain rates'. The entries and their order are those of
// setFromTriplets on the same triplets (a test compares them).
void ResistanceSystem::build_pattern(const std::vector<Connection>& cs) {
  const SystemLayout& l = layout_;
  const int p = l.per_grain, nb = l.n_box;
  const int64_t grains = l.grains, size = l.size();
  // Each grain's partners, itself included, sorted and unique (CSR over grains).
  std::vector<int64_t>&start = start_, &rank = rank_, &partners = partners_;
  std::vector<int32_t>& adj = adj_;
  start.assign(static_cast<size_t>(grains) + 1, 0);
  for (const Connection& c : cs) {
    ++start[c.i + 1];
    ++start[c.j + 1];
  }
  // Each grain's connections in their order (CSR over grains; the same counts).
  by_grain_start_.assign(start.begin(), start.end());
  rank.assign(static_cast<size_t>(grains), -1);  // among the connected grains
  int64_t connected = 0;
  for (int64_t g = 0; g < grains; ++g) {
    if (start[g + 1] > 0) {
      rank[g] = connected++;
      ++start[g + 1];  // the grain itself
    }
    start[g + 1] += start[g];
  }
  adj.resize(static_cast<size_t>(start[grains]));
  partners.assign(start.begin(), start.end() - 1);  // first the fill positions
  for (int64_t g = 0; g < grains; ++g)
    if (rank[g] >= 0) adj[partners[g]++] = static_cast<int32_t>(g);
  for (const Connection& c : cs) {
    adj[partners[c.i]++] = c.j;
    adj[partners[c.j]++] = c.i;
  }
  for (int64_t g = 0; g < grains; ++g) {
    auto b = adj.begin() + start[g], e = adj.begin() + start[g + 1];
    std::sort(b, e);
    partners[g] = std::unique(b, e) - b;
  }
  const bool any = !cs.empty();
  // Column starts, then rows, written into the matrix's own arrays.
  int64_t nnz = 0;
  for (int64_t g = 0; g < grains; ++g) nnz += p * (rank[g] >= 0 ? partners[g] * p + nb : 1);
  nnz += nb * (any ? connected * p + nb : 1);
  if (nnz > std::numeric_limits<int>::max()) throw std::length_error("the resistance matrix has over 2^31 entries");
  if (a_.rows() != size || a_.cols() != size) a_.resize(size, size);
  a_.makeCompressed();  // a no-op unless something left it uncompressed
  // The connections change at nearly every step, and the entries with them: room for a quarter
  // more, so that the arrays are not moved into fresh memory (page faults, a copy) at each step
  // that adds a few.
  if (nnz > a_.data().allocatedSize()) a_.data().reserve(nnz + nnz / 4 - a_.nonZeros());
  a_.resizeNonZeros(nnz);
  int* outer = a_.outerIndexPtr();
  int* out = a_.innerIndexPtr();
  outer[0] = 0;
  for (int64_t g = 0; g < grains; ++g)
    for (int a = 0; a < p; ++a) {
      const int* col = out;
      if (rank[g] < 0) {
        *out++ = static_cast<int>(g * p + a);
      } else {
        for (int64_t q = start[g]; q < start[g] + partners[g]; ++q)
          for (int b = 0; b < p; ++b) *out++ = static_cast<int>(adj[q] * int64_t{p} + b);
        for (int k = 0; k < nb; ++k) *out++ = static_cast<int>(l.box_unknown(k));
      }
      outer[g * p + a + 1] = outer[g * p + a] + static_cast<int>(out - col);
    }
  for (int k = 0; k < nb; ++k) {
    const int* col = out;
    if (!any) {
      *out++ = static_cast<int>(l.box_unknown(k));
    } else {
      for (int64_t g = 0; g < grains; ++g)
        if (rank[g] >= 0)
          for (int b = 0; b < p; ++b) *out++ = static_cast<int>(g * p + b);
      for (int m = 0; m < nb; ++m) *out++ = static_cast<int>(l.box_unknown(m));
    }
    outer[l.box_unknown(k) + 1] = outer[l.box_unknown(k)] + static_cast<int>(out - col);
  }
  // Where grain h's block is among grain g's partners (its slot in g's sorted adjacency).
  auto slot = [&](int64_t g, int64_t h) -> int64_t {
    const auto b = adj.begin() + start[g];
    return std::lower_bound(b, b + partners[g], static_cast<int32_t>(h)) - b;
  };
  // The diagonal: in a connected grain's column its own block (at its slot among its partners),
  // in a strain rate's column after the connected grains' rows; alone in any other column.
  diag_pos_.resize(static_cast<size_t>(size));
  for (int64_t k = 0; k < size; ++k) {
    int64_t at = outer[k];
    if (k < grains * p && rank[k / p] >= 0)
      at = grain_block(outer, p, k / p, static_cast<int>(k % p), slot(k / p, k / p)) + k % p;
    if (k >= grains * p && any) at += connected * p + (k - grains * p);
    diag_pos_[k] = static_cast<int32_t>(at);
  }
  // Each connection's blocks are found from its grains' slots (add_block): slots_[k][2 s + t] is
  // the slot of side t's grain among side s's grain's partners (side 0 grain i, side 1 grain j).
  slots_.resize(cs.size());
  for (size_t k = 0; k < cs.size(); ++k) {
    const int64_t g[2] = {cs[k].i, cs[k].j};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) slots_[k][2 * a + b] = static_cast<int32_t>(slot(g[a], g[b]));
  }
  // Filled with the starts as cursors (each ends at the next grain's start), then shifted back.
  for (int64_t g = 0; g < grains; ++g) by_grain_start_[g + 1] += by_grain_start_[g];
  by_grain_.resize(2 * cs.size());
  for (size_t k = 0; k < cs.size(); ++k) {
    by_grain_[by_grain_start_[cs[k].i]++] = static_cast<int32_t>(k);
    by_grain_[by_grain_start_[cs[k].j]++] = static_cast<int32_t>(k);
  }
  for (int64_t g = grains; g > 0; --g) by_grain_start_[g] = by_grain_start_[g - 1];
  by_grain_start_[0] = 0;
  connected_ = connected;
  pairs_.resize(cs.size());
  for (size_t k = 0; k < cs.size(); ++k) pairs_[k] = {cs[k].i, cs[k].j};
}

bool ResistanceSystem::assemble(const SystemLayout& l, const std::vector<Connection>& cs,
                                const std::vector<double>& radius, double shear_rate) {
  bool same = pairs_.size() == cs.size() && layout_.size() == l.size() && layout_.n_box == l.n_box &&
              layout_.shear == l.shear && a_.rows() == l.size();
  for (size_t k = 0; same && k < cs.size(); ++k) same = pairs_[k].first == cs[k].i && pairs_[k].second == cs[k].j;
  layout_ = l;
  if (!same) build_pattern(cs);
  const int n = local_size(l);
  // Each connection's G^T xi G, in parallel; then added in connection order (deterministic).
  local_.resize(cs.size() * static_cast<size_t>(n * n));
  parallel_for(static_cast<int64_t>(cs.size()), 256, [&](int64_t b, int64_t e) {
    for (int64_t k = b; k < e; ++k) {
      const Connection& c = cs[k];
      local_block(l, c, radius[c.i], radius[c.j], c.xi_n, c.xi_t, &local_[k * n * n]);
    }
  });
  double* val = a_.valuePtr();
  std::fill(val, val + a_.nonZeros(), 0.0);
  shear_rhs_.setZero(l.size());
  // On one thread connection by connection, which reads each local block once; the same sums.
  if (tbb::this_task_arena::max_concurrency() > 1) add_blocks(cs, shear_rate);
  else
    for (size_t k = 0; k < cs.size(); ++k) add_block(cs[k], &local_[k * n * n], slots_[k], shear_rate, shear_rhs_);
  return !same;
}

void ResistanceSystem::add_contact_stiffness(const std::vector<Connection>& cs, const std::vector<double>& radius,
                                             double shear_rate, linalg::Vector& rhs) {
  const int n = local_size(layout_);
  std::vector<double> loc(static_cast<size_t>(n * n));
  for (size_t k = 0; k < cs.size(); ++k) {
    const Connection& c = cs[k];
    if (c.k_n == 0 && c.k_t == 0) continue;
    local_block(layout_, c, radius[c.i], radius[c.j], c.k_n, c.k_t, loc.data());
    add_block(c, loc.data(), slots_[k], shear_rate, rhs);
  }
}

namespace {

// add_block's loops, with the unknowns a grain (P) and the box's strain rates (NB) known to the
// compiler, which unrolls them: the same additions in the same order as with run-time sizes.
template <int P, int NB>
void add_local(double* val, const int* outer, const int64_t g[2], const std::array<int32_t, 4>& slot,
               const int64_t partners[2], const int64_t rank[2], int64_t connected, int64_t box0, int n,
               const double* loc) {
  // Column a of side s's grain: the P rows of each side's grain at its slot, then the box's rows.
  // Local entry (row r, column q) is loc[r n + q]; each entry of the matrix takes one addition.
  for (int s = 0; s < 2; ++s)
    for (int a = 0; a < P; ++a) {
      const int q = s * P + a;
      for (int t = 0; t < 2; ++t) {
        double* v = val + grain_block(outer, P, g[s], a, slot[2 * s + t]);
        for (int b = 0; b < P; ++b) v[b] += loc[(t * P + b) * n + q];
      }
      double* vb = val + grain_block(outer, P, g[s], a, partners[s]);
      for (int k = 0; k < NB; ++k) vb[k] += loc[(2 * P + k) * n + q];
    }
  // A strain rate's column: the P rows of each grain at its rank among the connected grains, then
  // the box's rows.
  for (int k = 0; k < NB; ++k) {
    const int q = 2 * P + k;
    double* col = val + outer[box0 + k];
    for (int t = 0; t < 2; ++t) {
      double* v = col + rank[t] * P;
      for (int b = 0; b < P; ++b) v[b] += loc[(t * P + b) * n + q];
    }
    double* vb = col + connected * P;
    for (int m = 0; m < NB; ++m) vb[m] += loc[(2 * P + m) * n + q];
  }
}

// f(std::integral_constant<int, P>, std::integral_constant<int, NB>) with the unknowns of a grain
// (3 or 6) and the box's strain rates (0 to 3) as compile-time constants.
template <class F>
void with_sizes(int p, int nb, F&& f) {
  auto boxes = [&](auto pc) {
    switch (nb) {
      case 0: return f(pc, std::integral_constant<int, 0>{});
      case 1: return f(pc, std::integral_constant<int, 1>{});
      case 2: return f(pc, std::integral_constant<int, 2>{});
      default: return f(pc, std::integral_constant<int, 3>{});
    }
  };
  if (p == 3) boxes(std::integral_constant<int, 3>{});
  else boxes(std::integral_constant<int, 6>{});
}

}  // namespace

void ResistanceSystem::add_block(const Connection& c, const double* loc, const std::array<int32_t, 4>& slot,
                                 double shear_rate, linalg::Vector& rhs) {
  const SystemLayout& l = layout_;
  const int n = local_size(l);
  const int64_t g[2] = {c.i, c.j};
  const int64_t partners[2] = {partners_[c.i], partners_[c.j]}, rank[2] = {rank_[c.i], rank_[c.j]};
  double* val = a_.valuePtr();
  const int* outer = a_.outerIndexPtr();
  with_sizes(l.per_grain, l.n_box, [&](auto p, auto nb) {
    add_local<decltype(p)::value, decltype(nb)::value>(val, outer, g, slot, partners, rank, connected_,
                                                       l.box_unknown(0), n, loc);
  });
  if (l.shear)
    for (int r = 0; r < n - 1; ++r) rhs[local_to_global(l, c, r)] -= loc[r * n + (n - 1)] * shear_rate;
}

namespace {

// The part of add_local in grain g's columns and in its rows of the strain rates' columns, g
// being side s of a connection: the same additions as add_local's there. The local block is
// symmetric to the bit (local_block), so a column is read as the row it equals, in order.
template <int P, int NB>
void add_local_grain(double* val, const int* outer, int64_t g, int s, const std::array<int32_t, 4>& slot,
                     int64_t partners, int64_t rank, int64_t box0, int n, const double* loc) {
  for (int a = 0; a < P; ++a) {
    const double* column = loc + (s * P + a) * n;
    for (int t = 0; t < 2; ++t) {
      double* v = val + grain_block(outer, P, g, a, slot[2 * s + t]);
      for (int b = 0; b < P; ++b) v[b] += column[t * P + b];
    }
    double* vb = val + grain_block(outer, P, g, a, partners);
    for (int k = 0; k < NB; ++k) vb[k] += column[2 * P + k];
  }
  for (int k = 0; k < NB; ++k) {
    const double* column = loc + (2 * P + k) * n + s * P;
    double* v = val + outer[box0 + k] + rank * P;
    for (int b = 0; b < P; ++b) v[b] += column[b];
  }
}

}  // namespace

// add_block for every connection in their order, in parallel by grain: the columns of a grain,
// its rows of the strain rates' columns and its rows of the shear's right-hand side take the
// additions of its connections in their order, as add_block makes them, so the sums are the same
// bits; the strain rates' own block and rows then take every connection's in their order.
void ResistanceSystem::add_blocks(const std::vector<Connection>& cs, double shear_rate) {
  const SystemLayout& l = layout_;
  const int n = local_size(l), p = l.per_grain, nb = l.n_box;
  const int64_t box0 = l.box_unknown(0);
  double* val = a_.valuePtr();
  const int* outer = a_.outerIndexPtr();
  double* rhs = shear_rhs_.data();
  with_sizes(p, nb, [&](auto pc, auto nbc) {
    parallel_for(l.grains, 256, [&](int64_t g0, int64_t g1) {
      for (int64_t g = g0; g < g1; ++g)
        for (int32_t e = by_grain_start_[g]; e < by_grain_start_[g + 1]; ++e) {
          const int32_t k = by_grain_[e];
          const int s = cs[k].i == g ? 0 : 1;
          const double* loc = &local_[static_cast<size_t>(k) * n * n];
          add_local_grain<decltype(pc)::value, decltype(nbc)::value>(val, outer, g, s, slots_[k], partners_[g],
                                                                     rank_[g], box0, n, loc);
          if (l.shear)
            for (int b = 0; b < p; ++b) rhs[g * p + b] -= loc[(n - 1) * n + s * p + b] * shear_rate;
        }
    });
  });
  for (size_t k = 0; k < cs.size(); ++k) {
    const double* loc = &local_[k * n * n];
    for (int c = 0; c < nb; ++c) {
      double* vb = val + outer[box0 + c] + connected_ * p;
      for (int m = 0; m < nb; ++m) vb[m] += loc[(2 * p + m) * n + 2 * p + c];
    }
    if (l.shear)
      for (int r = 2 * p; r < n - 1; ++r) rhs[local_to_global(l, cs[k], r)] -= loc[r * n + (n - 1)] * shear_rate;
  }
}

linalg::SparseMatrix ResistanceSystem::sparsified(const std::vector<uint8_t>& keep, bool own_rotations) const {
  linalg::SparseMatrix m = a_;
  double* val = m.valuePtr();
  const int p = layout_.per_grain;
  const int* outer = m.outerIndexPtr();  // a_'s pattern until the prune below
  for (size_t k = 0; k < pairs_.size() && k < keep.size(); ++k) {
    if (keep[k]) continue;
    // The (i, j) and (j, i) blocks: the rows of one grain in the columns of the other.
    for (int a = 0; a < p; ++a) {
      std::fill_n(val + grain_block(outer, p, pairs_[k].first, a, slots_[k][1]), p, 0.0);
      std::fill_n(val + grain_block(outer, p, pairs_[k].second, a, slots_[k][2]), p, 0.0);
    }
  }
  if (own_rotations) {
    const int d = layout_.dim;
    const int64_t grains = layout_.grains * p;
    auto rotation = [&](int64_t k) { return k < grains && k % p >= d; };
    const int* rows = m.innerIndexPtr();
    for (int64_t col = 0; col < m.outerSize(); ++col)
      for (int q = outer[col]; q < outer[col + 1]; ++q) {
        const int64_t row = rows[q];
        const bool rr = rotation(row), rc = rotation(col);
        if ((rr || rc) && !(rr && rc && row / p == col / p)) val[q] = 0;
      }
  }
  m.prune(0.0, 0.0);
  m.makeCompressed();
  return m;
}

linalg::CoarseSpace stiff_directions(const SystemLayout& layout, const std::vector<Connection>& cs,
                                     const std::vector<double>& radius, double ratio) {
  const int n = local_size(layout);
  std::vector<Eigen::Triplet<double, int>> t;
  std::vector<int64_t> keys;
  int col = 0;
  double g[3 * 16];
  for (const Connection& c : cs) {
    const double normal = c.xi_n + c.k_n, tangential = c.xi_t + c.k_t, soft = ratio * c.xi_t;
    if (!(normal > soft) && !(tangential > soft)) continue;
    local_map(layout, c, radius[c.i], radius[c.j], g);  // row 0: the normal, then the tangents
    for (int row = 0; row < layout.dim; ++row) {
      if (!((row == 0 ? normal : tangential) > soft)) continue;
      const double* gr = g + row * n;
      for (int q = 0; q < n; ++q) {
        const int64_t k = local_to_global(layout, c, q);
        if (k >= 0 && gr[q] != 0) t.emplace_back(static_cast<int>(k), col, gr[q]);
      }
      keys.push_back(direction_key(layout.grains, c.i, c.j, row));
      ++col;
    }
  }
  linalg::CoarseSpace space({}, std::move(keys));
  space.w.resize(layout.size(), col);
  space.w.setFromTriplets(t.begin(), t.end());
  return space;
}

void ResistanceSystem::pin(int64_t k, double scale, linalg::Vector& rhs) {
  double* val = a_.valuePtr();
  const int* rows = a_.innerIndexPtr();
  const int* outer = a_.outerIndexPtr();
  for (int p = outer[k]; p < outer[k + 1]; ++p) {
    const int r = rows[p];
    if (r == k) continue;
    val[p] = 0;
    // The symmetric entry (k, r) in column r.
    const int* b = rows + outer[r];
    const int* e = rows + outer[r + 1];
    const int* hit = std::lower_bound(b, e, static_cast<int>(k));
    if (hit != e && *hit == k) val[hit - rows] = 0;
  }
  val[diag_pos_[k]] = scale;
  rhs[k] = 0;
}

size_t ResistanceSystem::bytes() const {
  return static_cast<size_t>(a_.nonZeros()) * (sizeof(double) + sizeof(int)) + slots_.size() * sizeof(slots_[0]) +
         local_.size() * sizeof(double) + diag_pos_.size() * sizeof(int32_t) +
         pairs_.size() * sizeof(std::pair<int32_t, int32_t>) +
         (by_grain_start_.size() + by_grain_.size()) * sizeof(int32_t);
}

}  // namespace silt::paste
