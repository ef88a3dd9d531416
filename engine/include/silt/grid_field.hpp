// Values on a regular grid of cells, as frames and VTK files read them, and values sampled along
// a line (a probe): plain data, written by the modules that have grids (the fluid).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace silt {

// A field on a regular grid of cells (a fluid's vorticity, velocity, pressure; analytic fields
// in tests): `components` values per cell (1: a scalar, 3: a vector, x y z interleaved) at the
// cell centres lo + (i + 1/2) h, x fastest. A 2D field has nz = 1 (its cells one h[2] thick).
struct GridField {
  std::string name;  // "vorticity", ...
  std::string unit;  // "1/s", ... ("" for none)
  int components = 1;
  int nx = 0, ny = 0, nz = 1;
  std::array<double, 3> lo{0, 0, 0}, h{1, 1, 1};
  std::vector<double> value;  // nx * ny * nz * components
  size_t cell(int i, int j, int k = 0) const { return (static_cast<size_t>(k) * ny + j) * nx + i; }
  double at(int i, int j, int k = 0, int c = 0) const { return value[cell(i, j, k) * components + c]; }
  bool same_grid(const GridField& o) const { return nx == o.nx && ny == o.ny && nz == o.nz && lo == o.lo && h == o.h; }
};

// A field sampled at points along a segment (a line probe, [[output.lines]] of a scene): s the
// distance from the start in units of the segment's length, x the points, value the field there.
struct LineSample {
  std::string name, field;
  std::vector<double> s, value;
  std::vector<std::array<double, 3>> x;
};

}  // namespace silt
