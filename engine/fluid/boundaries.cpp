#include "fluid/boundaries.hpp"

#include <algorithm>
#include <cstdint>

#include "core/assert.hpp"
#include "core/parallel.hpp"
#include "fluid/sweep_for.hpp"

namespace silt::fluid {
namespace {

// Lines per task of the ghost fills, about as the sweeps cut the grid (rows along x), so a
// thread fills the lines of the part of the grid it sweeps.
constexpr int64_t kLinesPerTask = 64;

// The place of a line along axis b (its position along b 0): t along the first other axis and k
// along the second (z, unless b is; 0 in 2D), padded indices from -1 to n + 1.
inline std::array<int64_t, 3> line_place(int b, int64_t t, int64_t k) {
  std::array<int64_t, 3> idx{0, 0, 0};
  idx[b == 0 ? 1 : 0] = t;
  idx[b == 2 ? 1 : 2] = k;
  return idx;
}
inline int64_t lines_across(const Layout& L, int b) { return L.n[b == 0 ? 1 : 0] + 3; }

// Calls f(q, idx) for every line along axis b (q: its padded index at position 0 along b; idx:
// its place along the other axes), in parallel.
template <class F>
void for_each_line(const Layout& L, int b, F&& f) {
  const int64_t n1 = lines_across(L, b), n2 = L.dim == 3 ? L.n[b == 2 ? 1 : 2] + 3 : 1;
  sweep_for(L.cells(), n1 * n2, kLinesPerTask, [&](int64_t l0, int64_t l1) {
    for (int64_t l = l0; l < l1; ++l) {
      const std::array<int64_t, 3> idx = line_place(b, l % n1 - 1, L.dim == 3 ? l / n1 - 1 : 0);
      f(L.at(idx[0], idx[1], idx[2]), idx);
    }
  });
}

// Along a periodic axis b, the ghosts of a block of contiguous values at index 0 along b (whole
// rows or planes): -1 from n - 1, n from 0 and n + 1 from 1.
inline void wrap_block(const Layout& L, int b, double* u, int64_t base, int64_t len) {
  const int64_t n = L.n[b], sb = L.s[b];
  std::copy_n(u + base + (n - 1) * sb, len, u + base - sb);
  std::copy_n(u + base, len, u + base + n * sb);
  std::copy_n(u + base + sb, len, u + base + (n + 1) * sb);
}

// Along a periodic x, the three ghosts at the ends of row j of plane k.
inline void wrap_row(const Layout& L, double* u, int64_t j, int64_t k) {
  const int64_t n = L.n[0];
  double* row = u + L.at(0, j, k);
  row[-1] = row[n - 1];
  row[n] = row[0];
  row[n + 1] = row[1];
}

// The ghosts along a periodic axis b of the arrays f (n cells, or n faces, the face n being face
// 0), over the whole padded extent of the other axes: along the last axis whole rows (2D) or
// planes (3D); along x in 2D three values at the ends of each row, the rows shared among the
// threads. (In 3D, x and y go a plane at a time: wrap_plane.)
template <size_t K>
void wrap_periodic_axis(const Layout& L, int b, const std::array<double*, K>& f) {
  if (b == L.dim - 1) {
    const int64_t base = b == 2 ? L.at(-1, -1, 0) : L.at(-1, 0);
    for (double* u : f) wrap_block(L, b, u, base, L.s[b]);
    return;
  }
  SILT_ASSERT(L.dim == 2 && b == 0, "in 3D the ghosts along x and y are wrapped a plane at a time");
  sweep_for(L.cells(), L.n[1] + 3, kLinesPerTask, [&](int64_t r0, int64_t r1) {
    for (double* u : f)
      for (int64_t r = r0; r < r1; ++r) wrap_row(L, u, r - 1, 0);
  });
}

// Along x the lines are the rows, visited one after the other, each touched only at its ends:
// without a hint every row costs two cache misses. Fetch the ends of the row 8 further on.
inline void prefetch_row_ends(const Layout& L, const double* line, int64_t n) {
  __builtin_prefetch(line + 8 * L.s[1] - 1, 1);
  __builtin_prefetch(line + 8 * L.s[1] + n, 1);
}

}  // namespace

double inflow_velocity(const Grid& g, int b, int side, int a, const std::array<double, 3>& x) {
  const Bc& bc = g.bc[b][side];
  double v = bc.velocity[a];
  if (!bc.parabolic) return v;
  for (int o = 0; o < g.dim; ++o) {
    if (o == b || g.periodic(o)) continue;
    const double xi = (x[o] - g.lo[o]) / (g.n[o] * g.h[o]);
    v *= 4 * xi * (1 - xi);
  }
  return v;
}

namespace {

// The lines of axis b (x or y, in 3D) within z plane k (padded index -1 .. n + 1): f(q, idx) as
// for_each_line calls it for them.
template <class F>
void lines_in_plane(const Layout& L, int b, int64_t k, F&& f) {
  for (int64_t t = -1; t < lines_across(L, b) - 1; ++t) {
    const std::array<int64_t, 3> idx = line_place(b, t, k);
    f(L.at(idx[0], idx[1], idx[2]), idx);
  }
}

// Along a periodic axis b (x or y, in 3D), the ghosts of the arrays f within z plane k.
template <size_t K>
void wrap_plane(const Layout& L, int b, int64_t k, const std::array<double*, K>& f) {
  for (double* u : f) {
    if (b == 1) wrap_block(L, 1, u, L.at(-1, 0, k), L.s[1]);
    else
      for (int64_t j = -1; j < L.n[1] + 2; ++j) wrap_row(L, u, j, k);
  }
}

// The ghosts at both ends of one line along a non-periodic axis b of velocity component a (q: the
// line's padded index at position 0 along b; idx: its place along the other axes).
void velocity_line(const Grid& g, const Layout& L, int b, int a, double* u, int64_t q,
                   const std::array<int64_t, 3>& idx) {
  const int64_t n = g.n[b], sb = L.s[b];
  const bool normal = a == b;
  double* line = u + q;  // line[i * sb]: position i along b
  auto at = [&](int64_t i) -> double& { return line[i * sb]; };
  if (b == 0) prefetch_row_ends(L, line, n);
  // A line of u_a on the plane of a wall across axis a holds that wall's normal velocity, 0, out to
  // its ghosts too, whichever axis is filled last: where a lid meets a side wall the corner's ghost
  // read the lid's velocity with the lid across y and 0 with it across x, and a cavity turned a
  // quarter had another vorticity at its corners (its enstrophy 6 % apart at 128^2).
  const auto wall = [&](int side) {
    const BcType t = g.bc[a][side].type;
    return t == BcType::kNoSlip || t == BcType::kFreeSlip;
  };
  const bool on_wall = !normal && ((idx[a] == 0 && wall(0)) || (idx[a] == g.n[a] && wall(1)));
  for (int side = 0; side < 2; ++side) {
    const Bc& bc = g.bc[b][side];
    const int64_t edge = side == 0 ? 0 : (normal ? n : n - 1);  // last value inside
    const int64_t out = side == 0 ? -1 : edge + 1;              // the ghost
    const int64_t in = side == 0 ? 1 : edge - 1;                // the value inside the face
    if (normal) {
      switch (bc.type) {
        case BcType::kNoSlip:
        case BcType::kFreeSlip:
          at(edge) = 0;
          at(out) = -at(in);
          break;
        case BcType::kInflow: {
          std::array<double, 3> x{};
          for (int o = 0; o < g.dim; ++o) x[o] = g.lo[o] + (static_cast<double>(idx[o]) + 0.5) * g.h[o];
          at(edge) = inflow_velocity(g, b, side, a, x);
          at(out) = at(edge);
          break;
        }
        default: at(out) = at(edge);  // outflow
      }
    } else if (on_wall) {
      at(out) = 0;
      if (side == 1) at(n + 1) = 0;
    } else {
      switch (bc.type) {
        case BcType::kNoSlip: at(out) = 2 * bc.velocity[a] - at(edge); break;
        case BcType::kInflow: {
          std::array<double, 3> x{};
          for (int o = 0; o < g.dim; ++o)
            x[o] = g.lo[o] + (static_cast<double>(idx[o]) + (o == a ? 0.0 : 0.5)) * g.h[o];
          x[b] = g.lo[b] + side * n * g.h[b];
          at(out) = 2 * inflow_velocity(g, b, side, a, x) - at(edge);
          break;
        }
        default: at(out) = at(edge);  // free slip, outflow
      }
      if (side == 1) at(n + 1) = at(n);  // the unused slot
    }
  }
}

// And of a cell-centred scalar under the pressure's conditions.
void pressure_line(const Grid& g, const Layout& L, int b, double* p, int64_t q) {
  const int64_t n = g.n[b], sb = L.s[b];
  double* line = p + q;
  auto at = [&](int64_t i) -> double& { return line[i * sb]; };
  if (b == 0) prefetch_row_ends(L, line, n);
  const double lo = g.pbc(b, 0) == PressureBc::kDirichlet ? -1.0 : 1.0;
  const double hi = g.pbc(b, 1) == PressureBc::kDirichlet ? -1.0 : 1.0;
  at(-1) = lo * at(0);
  at(n) = hi * at(n - 1);
  at(n + 1) = at(n);
}

constexpr int64_t kEveryPlane = INT64_MIN;

// The ghosts along axis b of the velocity components (K of them): within z plane k (3D, b = x or
// y), or on every line, in a parallel loop (k = kEveryPlane).
template <size_t K>
void velocity_axis(const Grid& g, const Layout& L, int b, const std::array<double*, K>& c, int64_t k) {
  if (g.periodic(b)) {
    if (k == kEveryPlane) wrap_periodic_axis<K>(L, b, c);
    else wrap_plane<K>(L, b, k, c);
    return;
  }
  for (int a = 0; a < static_cast<int>(K); ++a) {
    auto line = [&](int64_t q, const std::array<int64_t, 3>& idx) { velocity_line(g, L, b, a, c[a], q, idx); };
    if (k == kEveryPlane) for_each_line(L, b, line);
    else lines_in_plane(L, b, k, line);
  }
}

void pressure_axis(const Grid& g, const Layout& L, int b, double* p, int64_t k) {
  if (g.periodic(b)) {
    if (k == kEveryPlane) wrap_periodic_axis<1>(L, b, {p});
    else wrap_plane<1>(L, b, k, {p});
    return;
  }
  auto line = [&](int64_t q, const std::array<int64_t, 3>&) { pressure_line(g, L, b, p, q); };
  if (k == kEveryPlane) for_each_line(L, b, line);
  else lines_in_plane(L, b, k, line);
}

// Every axis in order, each over the whole padded extent of the others. In 3D the ghosts along x
// and along y of a z plane come from that plane alone, so one loop over the planes (-1 .. n + 1)
// makes both, x first (the y ghosts are whole rows, their ends x's): one parallel loop where
// there were two (at 32^3 a step runs about 100, each start and join some microseconds).
template <class Axis>
void fill_axes(const Grid& g, const Layout& L, Axis&& axis) {
  if (g.dim == 3) {
    sweep_for(L.cells(), L.n[2] + 3, 1, [&](int64_t k0, int64_t k1) {
      for (int64_t k = k0; k < k1; ++k) {
        axis(0, k - 1);
        axis(1, k - 1);
      }
    });
    axis(2, kEveryPlane);
    return;
  }
  for (int b = 0; b < g.dim; ++b) axis(b, kEveryPlane);
}

}  // namespace

void fill_velocity_ghosts(const Grid& g, const Layout& L, const std::array<double*, 3>& c) {
  fill_axes(g, L, [&](int b, int64_t k) {
    if (g.dim == 3) velocity_axis<3>(g, L, b, c, k);
    else velocity_axis<2>(g, L, b, {c[0], c[1]}, k);
  });
}

void fill_pressure_ghosts(const Grid& g, const Layout& L, double* p) {
  fill_axes(g, L, [&](int b, int64_t k) { pressure_axis(g, L, b, p, k); });
}

}  // namespace silt::fluid
