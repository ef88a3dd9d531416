// Arrays with one layer of ghost values around the grid, used inside a fluid step (the State
// holds the fields without ghosts). Every component and the pressure share one padded shape,
// (n0 + 3) x (n1 + 3) x (n2 + 3) (n2 + 3 -> 1 in 2D): index i runs from -1 to n + 1 along each
// axis, which covers the faces (0 .. n) with a ghost beyond each end and the cells (0 .. n - 1)
// with one ghost each side (one slot unused). Stencils then read neighbours at fixed strides
// without a branch.
#pragma once

#include <array>
#include <cstdint>

#include "fluid/grid.hpp"

namespace silt::fluid {

struct Layout {
  int dim = 2;
  std::array<int64_t, 3> n{1, 1, 1};
  std::array<int64_t, 3> s{1, 1, 0};  // strides; s[2] = 0 in 2D
  int64_t origin = 0;                 // offset of (0, 0, 0)
  int64_t size = 0;
  explicit Layout(const Grid& g) : dim(g.dim), n(g.n) {
    const int64_t p0 = n[0] + 3, p1 = n[1] + 3, p2 = dim == 3 ? n[2] + 3 : 1;
    s = {1, p0, dim == 3 ? p0 * p1 : 0};
    origin = 1 + p0 + (dim == 3 ? p0 * p1 : 0);
    size = p0 * p1 * p2;
  }
  Layout() = default;
  int64_t cells() const { return n[0] * n[1] * (dim == 3 ? n[2] : 1); }
  int64_t at(int64_t i, int64_t j, int64_t k = 0) const { return origin + i + j * s[1] + k * s[2]; }
};

// [lo, hi) of the index along axis b of the faces normal to axis a that the momentum equation
// updates: along a, the faces inside the box (a periodic axis: 0 .. n - 1, the face n being
// face 0; an outflow face is updated, a wall or an inflow face is given); along another axis,
// every cell.
inline std::array<int64_t, 2> update_range(const Grid& g, int a, int b) {
  if (b != a) return {0, g.n[b]};
  if (g.periodic(a)) return {0, g.n[a]};
  const int64_t lo = g.bc[a][0].type == BcType::kOutflow ? 0 : 1;
  const int64_t hi = g.bc[a][1].type == BcType::kOutflow ? g.n[a] + 1 : g.n[a];
  return {lo, hi};
}

}  // namespace silt::fluid
