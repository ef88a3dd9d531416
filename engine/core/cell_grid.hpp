// A grid of cells over bare positions, for finding the grains within a range of each other (Allen
// & Tildesley 1987, sec. 5.3). The DEM's neighbour lists (dem/neighbor_list.cpp) and the paste's
// count of connections before a run (paste/memory.cpp) search with it.
//
// Periodic directions are cut into whole cells at least `cutoff` wide; open directions span the
// grains' extent (they may leave the nominal domain). The cells are enlarged until there are at
// most kMaxCellsPerGrain per grain plus kMaxCellsExtra, whatever the box: a grain flying away, or
// grains tiny against a long periodic box, do not allocate a huge grid. Under Lees-Edwards the
// row of cells across the y boundary is shifted along x by the box's offset.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/parallel.hpp"
#include "silt/model.hpp"
#include "silt/periodic_image.hpp"
#include "silt/vec.hpp"

namespace silt {

constexpr double kMaxCellsPerGrain = 4, kMaxCellsExtra = 4096;

struct CellGrid {
  int n[3] = {1, 1, 1};
  double lo[3] = {0, 0, 0};
  double inv_size[3] = {1, 1, 1};
  bool wrap[3] = {false, false, false};
  double le_shift = 0;     // Lees-Edwards offset in x cells (the image above is shifted by it)
  bool may_repeat = true;  // a stencil may name a cell twice (a periodic direction of few cells)
  int64_t count() const { return int64_t{n[0]} * n[1] * n[2]; }
};

// The grid for n grains at x (D coordinates each) in `box`, cells at least `cutoff` wide.
template <int D>
CellGrid make_cell_grid(const double* x, int64_t n, const Box& box, double cutoff) {
  CellGrid g;
  double xmin[3], xmax[3];
  for (int k = 0; k < D; ++k) {
    xmin[k] = 1e308;
    xmax[k] = -1e308;
  }
  for (int64_t i = 0; i < n; ++i)
    for (int k = 0; k < D; ++k) {
      const double xk = x[D * i + k];
      if (!std::isfinite(xk)) continue;  // a grain gone to infinity (the step reports it) takes no cells
      xmin[k] = std::min(xmin[k], xk);
      xmax[k] = std::max(xmax[k], xk);
    }
  const double cap = kMaxCellsPerGrain * static_cast<double>(n) + kMaxCellsExtra;
  double size[3] = {cutoff, cutoff, cutoff};
  for (int grow = 0; grow < 2100; ++grow) {
    double total = 1;
    for (int k = 0; k < D; ++k) {
      if (box.periodic[k]) {
        g.wrap[k] = true;
        // (A box length gone non-finite, which the box's stage reports, gets one cell.)
        const double cells = std::floor(box.len[k] / size[k]);
        g.n[k] = std::isfinite(cells) ? static_cast<int>(std::clamp(cells, 1.0, 1e9)) : 1;
        g.lo[k] = box.lo[k];
        g.inv_size[k] = g.n[k] / box.len[k];
      } else {
        g.lo[k] = xmin[k];
        const double span = std::max(0.0, xmax[k] - xmin[k]);
        g.n[k] = static_cast<int>(std::min(1e9, std::floor(span / size[k]))) + 1;
        g.inv_size[k] = 1.0 / size[k];
      }
      total *= g.n[k];
    }
    if (total <= cap) break;
    for (int k = 0; k < D; ++k) size[k] *= 2;
  }
  if (box.lees_edwards) g.le_shift = box.le_offset * g.inv_size[0];
  // An offset outside [0, L_x] is a broken box (the box's stage reports it): no shift.
  if (!(g.le_shift >= 0 && g.le_shift <= g.n[0])) g.le_shift = 0;
  g.may_repeat = false;
  for (int k = 0; k < D; ++k)
    if (g.wrap[k] && g.n[k] < (k == 0 && box.lees_edwards ? 4 : 3)) g.may_repeat = true;
  return g;
}

template <int D>
int32_t cell_index(const CellGrid& g, const double* x) {
  int c[3] = {0, 0, 0};
  for (int k = 0; k < D; ++k) {
    // Clamped before the conversion: a coordinate far away (or not finite) is the edge cell.
    const double f = std::floor((x[k] - g.lo[k]) * g.inv_size[k]);
    int q = std::isfinite(f) ? static_cast<int>(std::clamp(f, -2e9, 2e9)) : 0;
    if (g.wrap[k]) {
      q %= g.n[k];
      if (q < 0) q += g.n[k];
    } else {
      q = std::clamp(q, 0, g.n[k] - 1);
    }
    c[k] = q;
  }
  return static_cast<int32_t>((int64_t{c[2]} * g.n[1] + c[1]) * g.n[0] + c[0]);
}

// The distinct cells around cell `c` (fewer than 3^D when a periodic direction has < 3 cells;
// at most 3 z-layers x (3 + 4 + 4) cells). Under Lees-Edwards, the row across the y boundary is
// shifted along x by the offset: a grain there appears at x + offset above the box (x - offset
// below), so the x range scanned across the boundary is moved by the shift and widened by one
// cell for its fractional part.
constexpr int kMaxStencil = 36;
template <int D>
int stencil(const CellGrid& g, int32_t c, int32_t* out) {
  int cc[3] = {static_cast<int>(c % g.n[0]), static_cast<int>((c / g.n[0]) % g.n[1]),
               static_cast<int>(c / (int64_t{g.n[0]} * g.n[1]))};
  int count = 0;
  const int zr = D == 3 ? 1 : 0;
  for (int dz = -zr; dz <= zr; ++dz)
    for (int dy = -1; dy <= 1; ++dy) {
      const int qy = cc[1] + dy;
      const bool across = g.le_shift != 0 && (qy < 0 || qy >= g.n[1]);
      int x0 = cc[0] - 1, x1 = cc[0] + 1;
      if (across) {
        const double base = cc[0] + (qy >= g.n[1] ? -g.le_shift : g.le_shift);
        x0 = static_cast<int>(std::floor(base)) - 1;
        x1 = x0 + 3;
      }
      for (int qx = x0; qx <= x1; ++qx) {
        int q[3] = {qx, qy, cc[2] + dz};
        bool ok = true;
        for (int k = 0; k < D; ++k) {
          if (q[k] < 0 || q[k] >= g.n[k]) {
            if (!g.wrap[k]) {
              ok = false;
              break;
            }
            q[k] = ((q[k] % g.n[k]) + g.n[k]) % g.n[k];
          }
        }
        if (!ok) continue;
        const int32_t id = static_cast<int32_t>((int64_t{q[2]} * g.n[1] + q[1]) * g.n[0] + q[0]);
        if (!g.may_repeat || std::find(out, out + count, id) == out + count) out[count++] = id;
      }
    }
  return count;
}

// Counting sort of n grains into the cells of g: cell_of[i] is grain i's cell, and the grains of
// cell c are items[start[c]] to items[start[c + 1] - 1], in index order.
template <int D>
void sort_into_cells(const CellGrid& g, const double* x, int64_t n, std::vector<int32_t>& cell_of,
                     std::vector<int32_t>& start, std::vector<int32_t>& items) {
  cell_of.resize(n);
  start.assign(g.count() + 1, 0);
  parallel_for(n, 4096, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i) cell_of[i] = cell_index<D>(g, &x[D * i]);
  });
  for (int64_t i = 0; i < n; ++i) ++start[cell_of[i] + 1];
  for (int64_t c = 0; c < g.count(); ++c) start[c + 1] += start[c];
  items.resize(n);
  std::vector<int32_t> pos(start.begin(), start.end() - 1);
  for (int64_t i = 0; i < n; ++i) items[pos[cell_of[i]]++] = static_cast<int32_t>(i);
}

// Calls f(i, j, d) once for every pair i < j of the n grains at x whose cells neighbour each
// other in a grid of cells at least `range` wide, d the nearest image of x_i - x_j: every pair
// closer than `range` is among them (serially, in the order of i).
template <int D, class F>
void for_each_pair_in_range(const double* x, int64_t n, const Box& box, double range, F&& f) {
  const CellGrid g = make_cell_grid<D>(x, n, box, range);
  std::vector<int32_t> cell_of, start, items;
  sort_into_cells<D>(g, x, n, cell_of, start, items);
  const PeriodicImage<D> img(box);
  int32_t cells[kMaxStencil];
  for (int64_t i = 0; i < n; ++i) {
    const int nc = stencil<D>(g, cell_of[i], cells);
    for (int q = 0; q < nc; ++q)
      for (int32_t t = start[cells[q]]; t < start[cells[q] + 1]; ++t) {
        const int32_t j = items[t];
        if (j <= i) continue;
        Vec<D> d = at<D>(x, i) - at<D>(x, j);
        img.apply(d);
        f(i, j, d);
      }
  }
}

}  // namespace silt
