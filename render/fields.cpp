// Analytic vorticity fields for tests and demonstrations, until the fluid module provides real ones.
#include <cmath>
#include <numbers>

#include "silt/render.hpp"

namespace silt::render {
namespace {

GridField grid(int nx, int ny, int nz, int components) {
  GridField g;
  g.name = "vorticity";
  g.components = components;
  g.nx = nx;
  g.ny = ny;
  g.nz = nz;
  g.value.resize(static_cast<size_t>(nx) * ny * nz * components);
  return g;
}

}  // namespace

// Lamb-Oseen vortex: omega(r) = Gamma / (pi rc^2) exp(-r^2 / rc^2) (Saffman 1992, sec. 2.4).
GridField lamb_oseen_vorticity(int nx, int ny, std::array<double, 2> lo, std::array<double, 2> hi,
                               std::array<double, 2> centre, double gamma, double rc) {
  GridField g = grid(nx, ny, 1, 1);
  g.lo = {lo[0], lo[1], 0};
  g.h = {(hi[0] - lo[0]) / nx, (hi[1] - lo[1]) / ny, 1};
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = lo[0] + (i + 0.5) * g.h[0] - centre[0];
      const double y = lo[1] + (j + 0.5) * g.h[1] - centre[1];
      g.value[g.cell(i, j)] = gamma / (std::numbers::pi * rc * rc) * std::exp(-(x * x + y * y) / (rc * rc));
    }
  return g;
}

// Taylor-Green cell on [0, L]^2: u = u0 sin(kx) cos(ky), v = -u0 cos(kx) sin(ky), k = 2 pi / L,
// so omega = dv/dx - du/dy = 2 u0 k sin(kx) sin(ky).
GridField taylor_green_vorticity(int nx, int ny, double length, double u0) {
  GridField g = grid(nx, ny, 1, 1);
  g.h = {length / nx, length / ny, 1};
  const double k = 2 * std::numbers::pi / length;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      g.value[g.cell(i, j)] = 2 * u0 * k * std::sin(k * (i + 0.5) * g.h[0]) * std::sin(k * (j + 0.5) * g.h[1]);
  return g;
}

// 3D Taylor-Green vortex on [0, L]^3 (Taylor & Green 1937; its initial condition):
//   u = u0 sin(kx) cos(ky) cos(kz),  v = -u0 cos(kx) sin(ky) cos(kz),  w = 0,  k = 2 pi / L.
// Its curl, term by term:
//   omega_x = dw/dy - dv/dz = -u0 k cos(kx) sin(ky) sin(kz)
//   omega_y = du/dz - dw/dx = -u0 k sin(kx) cos(ky) sin(kz)
//   omega_z = dv/dx - du/dy = 2 u0 k sin(kx) sin(ky) cos(kz)
// (omega_z at z = 0 is the 2D cell's vorticity).
GridField taylor_green_vorticity_3d(int n, double length, double u0) {
  GridField g = grid(n, n, n, 3);
  const double h = length / n, k = 2 * std::numbers::pi / length;
  g.h = {h, h, h};
  for (int c = 0; c < n; ++c)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = k * (i + 0.5) * h, y = k * (j + 0.5) * h, z = k * (c + 0.5) * h;
        double* w = &g.value[3 * g.cell(i, j, c)];
        w[0] = -u0 * k * std::cos(x) * std::sin(y) * std::sin(z);
        w[1] = -u0 * k * std::sin(x) * std::cos(y) * std::sin(z);
        w[2] = 2 * u0 * k * std::sin(x) * std::sin(y) * std::cos(z);
      }
  return g;
}

}  // namespace silt::render
