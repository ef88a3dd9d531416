#include "paste/memory.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/cell_grid.hpp"
#include "paste/params.hpp"
#include "paste/resistance.hpp"
#include "paste/system.hpp"
#include "silt/linalg.hpp"

namespace silt::paste {
namespace {

// Random close packing: the densest a compression or an imposed pressure brings the grains to
// (disks of a few sizes, Peyneau 2009 sec. 2.3.2: 0.836; monodisperse spheres 0.64).
double jammed_fraction(int dim) { return dim == 2 ? 0.84 : 0.64; }

double solid_fraction(const Model& m) {
  double grains = 0, box = 1;
  for (int64_t i = 0; i < m.n_grains; ++i) grains += grain_volume(m.dim, m.init.radius[i]);
  for (int a = 0; a < m.dim; ++a) box *= m.box.len[a];
  return box > 0 ? grains / box : 0;
}

// The solid fraction whose connections the run will solve with at most.
double run_fraction(const Model& m, double phi0) {
  const double jam = jammed_fraction(m.dim);
  if (m.box_control.on) return std::max(phi0, jam);
  if (m.prepare.compress)
    return std::max(phi0, m.prepare.phi > 0 ? m.prepare.phi : jam / std::pow(m.prepare.dilation, m.dim));
  return phi0;
}

// The pairs of grains whose gap is at most h_max once every centre and the box are scaled by
// `scale` about the box's low corner (radii kept). A sheared box starts unsheared (its offset
// zero): the plain periodic neighbours.
template <int D>
std::vector<std::array<int32_t, 2>> connected_pairs(const Model& m, double scale, double h_max) {
  const int64_t n = m.n_grains;
  Box box = m.box;
  box.le_offset = 0;
  for (int a = 0; a < D; ++a) box.len[a] *= scale;
  std::vector<double> x(static_cast<size_t>(n * D));
  for (int64_t i = 0; i < n; ++i)
    for (int a = 0; a < D; ++a) x[D * i + a] = m.box.lo[a] + scale * (m.init.x[D * i + a] - m.box.lo[a]);
  std::vector<std::array<int32_t, 2>> out;
  const double* r = m.init.radius.data();
  for_each_pair_in_range<D>(x.data(), n, box, 2 * m.r_max + h_max, [&](int64_t i, int64_t j, const Vec<D>& d) {
    if (d.norm() - r[i] - r[j] <= h_max) out.push_back({static_cast<int32_t>(i), static_cast<int32_t>(j)});
  });
  return out;
}

}  // namespace

PasteMemory estimate_paste_memory(const Model& m) {
  const PasteParams& p = m.params.get<PasteParams>();
  PasteMemory e;
  const int64_t n = m.n_grains;
  if (n <= 0) return e;
  const double phi0 = solid_fraction(m);
  e.phi = run_fraction(m, phi0);
  const double scale = phi0 > 0 && e.phi > phi0 ? std::pow(phi0 / e.phi, 1.0 / m.dim) : 1.0;
  const double h_max = p.h_max_over_a * p.a;
  const auto pairs = m.dim == 2 ? connected_pairs<2>(m, scale, h_max) : connected_pairs<3>(m, scale, h_max);
  const auto c = static_cast<int64_t>(pairs.size());
  e.connections = c;

  const SystemLayout l = make_layout(m, n);
  const int64_t pg = l.per_grain, nb = l.n_box, size = l.size();
  std::vector<uint8_t> linked(static_cast<size_t>(n), 0);
  for (const auto& [i, j] : pairs) linked[i] = linked[j] = 1;
  const auto n_linked = static_cast<int64_t>(std::count(linked.begin(), linked.end(), 1));

  // Xi's pattern, as ResistanceSystem builds it: every diagonal entry, the whole diagonal block
  // of a connected grain, the two blocks of every connection, and the box rows and columns of the
  // connected grains (for `b` unknowns a grain).
  auto pattern_entries = [&](int64_t b) {
    int64_t k = n_linked * b * b + (n - n_linked) * b + 2 * c * b * b + nb;
    if (c > 0 && nb > 0) k += 2 * n_linked * b * nb + nb * nb - nb;
    return k;
  };
  e.entries = pattern_entries(pg);

  // CHOLMOD's analysis of the grains' blocks (the box's strain rates one more block, dense).
  const int64_t nodes = n + (nb > 0 ? 1 : 0);
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(nodes + 2 * c + 2 * n_linked));
  for (int64_t k = 0; k < nodes; ++k) t.emplace_back(static_cast<int>(k), static_cast<int>(k), 1.0);
  for (const auto& [i, j] : pairs) {
    t.emplace_back(i, j, 1.0);
    t.emplace_back(j, i, 1.0);
  }
  if (nb > 0)
    for (int64_t i = 0; i < n; ++i)
      if (linked[i]) {
        t.emplace_back(static_cast<int>(i), static_cast<int>(n), 1.0);
        t.emplace_back(static_cast<int>(n), static_cast<int>(i), 1.0);
      }
  linalg::SparseMatrix pattern(nodes, nodes);
  pattern.setFromTriplets(t.begin(), t.end());
  const bool factored = p.solver.method != linalg::Method::kCg;
  // With the rotations' own blocks only (factor_pcg), the factor is the translations' (dim a
  // grain) and a dense rot x rot block per grain, which fills nothing in.
  const bool own = p.own_rotations && p.solver.method == linalg::Method::kFactorPcg;
  const int64_t fb = own ? l.dim : pg;
  linalg::FactorSize f;
  if (factored) f = linalg::block_factor_size(pattern, static_cast<int>(fb));
  if (factored && own) {
    f.entries += n * l.rot * l.rot;
    f.integers += 3 * n * l.rot;
  }
  e.factor = f.factor_bytes();
  // With factor_precision = single, the factor's values again as floats (the preconditioner's).
  if (p.solver.method == linalg::Method::kFactorPcg && p.solver.single_factor)
    e.factor += 4.0 * static_cast<double>(f.entries);
  // The factorised matrix's entries: Xi's, or the translations' and the rotations' own blocks.
  const int64_t factored_entries = own ? pattern_entries(fb) + n * l.rot * l.rot : e.entries;

  // Held between steps: the matrix (values and rows, column starts), each connection's local
  // G^T xi G (local_size^2 doubles) and its grains' slots (4 x 4 bytes), the connections themselves, the
  // diagonal's positions, a score of vectors of the unknowns (CG's, the factor's solves, the right-hand side, the
  // adaptive step's copies); with factor_pcg, the state's copy of the factorised matrix (n, nnz,
  // columns, rows, values as doubles), twice (the restart point holds the state too).
  const auto dn = static_cast<double>(size), dc = static_cast<double>(c), dnz = static_cast<double>(e.entries);
  const double nl = local_size(l);
  const double grains = static_cast<double>(n);
  // And the pattern's work arrays and each grain's connections (per grain, per connection end).
  e.held = 12 * dnz + 4 * dn + 8 * nl * nl * dc + dc * (sizeof(Connection) + 12 + 16) + 4 * dn + 20 * 8 * dn +
           24 * grains + 2 * 4 * (2 * dc + grains);
  if (p.solver.method == linalg::Method::kFactorPcg)
    e.held += 2 * 8 * (3 + dn + 2 * static_cast<double>(factored_entries));
  // Within a step: the numerical factorisation's update matrix (with a sparser copy of Xi when
  // only the stiff connections are factorised); a new pattern is written in place.
  double factor_peak = factored ? f.workspace_bytes() + 8 * dn : 0;
  if (factored && (p.factor_gap_over_a < p.h_max_over_a || own)) factor_peak += 12 * dnz;
  e.transient = factor_peak;
  return e;
}

}  // namespace silt::paste
