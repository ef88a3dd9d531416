// Verlet neighbour lists built from a cell list (Allen & Tildesley 1987, sec. 5.3).
//
// A pair (i, j), i < j, is listed when |d_ij| < r_i + r_j + skin; the list stays valid until
// twice the largest displacement since the build (relative to the affine flow of a deforming
// box), plus the affine strain times the list range, exceeds the skin. Rows are sorted by j, so
// the list, and everything summed over it, is the same whatever the number of threads. Pairs of two frozen grains are
// never listed.
//
// Above Model::kSortMin grains, each build also renumbers the grains in cell order (LAMMPS's
// atom sorting): a flowing bed scatters neighbours in memory, and the pair loop then waits on
// cache misses. Every per-grain array moves with the grains (particle_id keeps identities), and
// the tangential histories follow their pairs through the permutation.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/assert.hpp"
#include "core/buffers.hpp"
#include "core/cell_grid.hpp"
#include "core/parallel.hpp"
#include "dem/contact_candidates.hpp"
#include "dem/module.hpp"
#include "dem/pair_schedule.hpp"
#include "dem/stages.hpp"
#include "silt/periodic_image.hpp"

namespace silt::dem {
namespace {

// Renumber the grains in the order of sc.cell_items (by cell, then by index). Returns false when
// they already are in that order. Afterwards sc.perm[new] = old and the cell arrays follow.
template <int D>
bool permute_to_cell_order(State& s, DemWorkspace& sc) {
  const int64_t n = s.n;
  bool identity = true;
  for (int64_t k = 0; k < n && identity; ++k) identity = sc.cell_items[k] == k;
  if (identity) return false;
  sc.perm.assign(sc.cell_items.begin(), sc.cell_items.end());
  // Row k of an array (n rows of `row` bytes) becomes its row perm[k], gathered from a copy in
  // one reused buffer (the arrays have several element types).
  auto renumber = [&](void* data, size_t row) {
    sc.permute_buf.resize(static_cast<size_t>(n) * row);
    const std::byte* old = sc.permute_buf.data();
    std::memcpy(sc.permute_buf.data(), data, static_cast<size_t>(n) * row);
    auto* dst = static_cast<std::byte*>(data);
    parallel_for(n, 4096, [&](int64_t b, int64_t e) {
      for (int64_t k = b; k < e; ++k) std::memcpy(dst + k * row, old + sc.perm[k] * row, row);
    });
  };
  // Every field that follows the grains (silt/fields.hpp), whatever module owns it.
  for_each_field(s, [&](const FieldInfo& f, auto& v) {
    if constexpr (kIsArray<std::remove_cvref_t<decltype(v)>>) {
      if (!follows_grains(f.extent) || v.empty()) return;
      const int64_t items = extent_size(s, f.extent);
      if (static_cast<int64_t>(v.size()) != items || items % n != 0) return;
      renumber(v.data(), static_cast<size_t>(items / n) * sizeof(v[0]));
    }
  });
  renumber(sc.cell_of.data(), sizeof(int32_t));
  for (int64_t k = 0; k < n; ++k) sc.cell_items[k] = static_cast<int32_t>(k);
  return true;
}

// Returns whether the grains were renumbered.
template <int D>
bool rebuild(const Model& m, State& s, DemWorkspace& sc) {
  const int64_t n = s.n;
  const double skin = m.skin;
  const double cutoff = m.interaction_range();
  const CellGrid g = make_cell_grid<D>(s.particle_x.data(), n, s.box, cutoff);
  // Grains in a cell stay in index order.
  sort_into_cells<D>(g, s.particle_x.data(), n, sc.cell_of, sc.cell_start, sc.cell_items);
  // In cell order (renumbered now or already), grain j > i lies in a cell after i's or later in
  // i's own: the search skips the cells before it, about half of them.
  const bool in_order = m.sort_grains && n > Model::kSortMin;
  const bool sorted = in_order && permute_to_cell_order<D>(s, sc);
  // Keep the springs of the old list for the new one: only its pairs that hold one (most listed
  // pairs do not touch, and would carry zeros; a -0 is kept), as rows of partners and springs.
  // The new list then reuses the State's arrays.
  const bool had_list = static_cast<int64_t>(s.nbr_start.size()) == n + 1;
  sc.old_start.assign(n + 1, 0);
  sc.old_j.clear();
  sc.old_hist.clear();
  if (had_list) {
    for (int64_t i = 0; i < n; ++i) {
      for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
        if (!any_bit_set(&s.pair_hist[D * p], D)) continue;
        sc.old_j.push_back(s.pair_j[p]);
        for (int k = 0; k < D; ++k) sc.old_hist.push_back(s.pair_hist[D * p + k]);
      }
      sc.old_start[i + 1] = static_cast<int32_t>(sc.old_j.size());
    }
  }
  const PeriodicImage<D> img(s.box);
  // The cells around grain i's cell (at most 3 z-layers x (3 + 4 + 4) cells: rows across a
  // sheared boundary take 4); grains come mostly in cell order, so the last stencil is reused.
  struct Stencil {
    int32_t cell = -1;
    int count = 0;
    int32_t cells[kMaxStencil];
  };
  // visit(i, st, f): calls f(j) for every listed partner j > i, in no particular order.
  auto visit = [&](int64_t i, Stencil& st, auto&& f) {
    if (sc.cell_of[i] != st.cell) {
      st.cell = sc.cell_of[i];
      st.count = stencil<D>(g, st.cell, st.cells);
    }
    const int nc = st.count;
    const int32_t* cells = st.cells;
    const auto xi = at<D>(s.particle_x.data(), i);
    const double ri = s.particle_r[i];
    const bool fi = s.particle_frozen[i];
    for (int q = 0; q < nc; ++q) {
      int32_t t0 = sc.cell_start[cells[q]];
      if (in_order) {
        if (cells[q] < st.cell) continue;
        if (cells[q] == st.cell) t0 = static_cast<int32_t>(i) + 1;
      }
      for (int32_t t = t0; t < sc.cell_start[cells[q] + 1]; ++t) {
        const int32_t j = sc.cell_items[t];
        if (j <= i || (fi && s.particle_frozen[j])) continue;
        Vec<D> d = xi - at<D>(s.particle_x.data(), j);
        img.apply(d);
        const double reach = ri + s.particle_r[j] + skin;
        if (d.squaredNorm() < reach * reach) f(j);
      }
    }
  };
  // One search: the partners of each fixed chunk of rows go to that chunk's buffer, then to the
  // list once the row lengths are known.
  constexpr int64_t kChunk = 512;
  const int64_t n_chunks = (n + kChunk - 1) / kChunk;
  sc.row_count.resize(n);
  if (static_cast<int64_t>(sc.chunk_j.size()) < n_chunks) sc.chunk_j.resize(n_chunks);
  parallel_for(n_chunks, 1, [&](int64_t cb, int64_t ce) {
    Stencil st;
    for (int64_t k = cb; k < ce; ++k) {
      std::vector<int32_t>& found = sc.chunk_j[k];
      found.clear();
      for (int64_t i = k * kChunk; i < std::min(n, (k + 1) * kChunk); ++i) {
        const size_t before = found.size();
        visit(i, st, [&](int32_t j) { found.push_back(j); });
        sc.row_count[i] = static_cast<int32_t>(found.size() - before);
      }
    }
  });
  s.nbr_start.assign(n + 1, 0);
  for (int64_t i = 0; i < n; ++i) s.nbr_start[i + 1] = s.nbr_start[i] + sc.row_count[i];
  const int64_t np = s.nbr_start[n];
  resize_tight(s.pair_j, np);
  resize_tight(s.pair_i, np);
  assign_tight(s.pair_hist, np * D, 0.0);
  assign_tight(s.pair_f, np * D, 0.0);
  // A new pair holds nothing until the force pass finds it touching; a carried spring is marked
  // as held, so that the pass (or the candidate selection) clears it if the pair is apart.
  assign_tight(s.pair_touch, static_cast<size_t>(np), uint8_t{0});
  // Sort row i, name its first grain, and carry the tangential springs of pairs that were
  // already listed (old rows are sorted). With a renumbering, the pair may now be listed the
  // other way round: its elongation, measured from the first grain's side, changes sign.
  auto finish_row = [&](int64_t i) {
    int32_t* row = s.pair_j.data() + s.nbr_start[i];
    const int32_t c = sc.row_count[i];
    std::sort(row, row + c);
    std::fill(s.pair_i.begin() + s.nbr_start[i], s.pair_i.begin() + s.nbr_start[i] + c, static_cast<int32_t>(i));
    if (!had_list) return;
    for (int32_t q = 0; q < c; ++q) {
      const int32_t oi = sorted ? sc.perm[i] : static_cast<int32_t>(i);
      const int32_t oj = sorted ? sc.perm[row[q]] : row[q];
      const int32_t lo = std::min(oi, oj), hi = std::max(oi, oj);
      const int32_t* ob = sc.old_j.data() + sc.old_start[lo];
      const int32_t* oe = sc.old_j.data() + sc.old_start[lo + 1];
      const int32_t* hit = std::lower_bound(ob, oe, hi);
      if (hit != oe && *hit == hi) {
        const int64_t op = hit - sc.old_j.data();
        const double sign = oi < oj ? 1.0 : -1.0;
        for (int k = 0; k < D; ++k) s.pair_hist[D * (s.nbr_start[i] + q) + k] = sign * sc.old_hist[D * op + k];
        s.pair_touch[s.nbr_start[i] + q] = 1;
      }
    }
  };
  parallel_for(n_chunks, 1, [&](int64_t cb, int64_t ce) {
    for (int64_t ch = cb; ch < ce; ++ch) {
      const int64_t b = ch * kChunk, e = std::min(n, (ch + 1) * kChunk);
      std::copy(sc.chunk_j[ch].begin(), sc.chunk_j[ch].end(), s.pair_j.begin() + s.nbr_start[b]);
      for (int64_t i = b; i < e; ++i) finish_row(i);
    }
  });
  std::fill(s.particle_disp.begin(), s.particle_disp.end(), 0.0);
  s.nbr_strain = 0;
  s.nbr_max_disp = 0;
  s.nbr_valid = true;
  sc.new_schedule(n, s.nbr_start, s.pair_j);
  ++s.nbr_builds;
  return sorted;
}

template <int D>
bool update(const Model& m, State& s, DemWorkspace& w) {
  // Two grains approached by at most twice the largest displacement relative to the flow, plus
  // the affine strain times their separation (at most the list range).
  const bool stale = !s.nbr_valid || 2 * s.nbr_max_disp + s.nbr_strain * m.interaction_range() > m.skin - m.pair_gap;
  const bool renumbered = stale && rebuild<D>(m, s, w);
  update_candidates(m, s, w, stale);
  return renumbered;
}

}  // namespace

bool update_neighbors(const Model& m, State& s, DemWorkspace& w) {
  const bool renumbered = m.dim == 2 ? update<2>(m, s, w) : update<3>(m, s, w);
  // Post: a valid list in CSR form, its per-pair arrays as long as it.
  const int64_t np = s.n_pairs();
  SILT_ASSERT(has_pair_list(s) && s.nbr_start[s.n] == np, "the pair list's row starts do not span it");
  SILT_ASSERT(static_cast<int64_t>(s.pair_i.size()) == np && static_cast<int64_t>(s.pair_f.size()) == np * m.dim &&
                  static_cast<int64_t>(s.pair_hist.size()) == np * m.dim &&
                  static_cast<int64_t>(s.pair_touch.size()) == np,
              "a per-pair array is not as long as the pair list");
  return renumbered;
}

}  // namespace silt::dem
