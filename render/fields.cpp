// Analytic vorticity fields for tests and demonstrations, until the fluid module provides real ones.
#include <cmath>

#include "silt/render.hpp"

namespace silt::render {

// Lamb-Oseen vortex: omega(r) = Gamma / (pi rc^2) exp(-r^2 / rc^2) (Saffman 1992, sec. 2.4).
ScalarGrid lamb_oseen_vorticity(int nx, int ny, std::array<double, 2> lo, std::array<double, 2> hi,
                                std::array<double, 2> centre, double gamma, double rc) {
  ScalarGrid g;
  g.name = "vorticity";
  g.nx = nx;
  g.ny = ny;
  g.lo = {lo[0], lo[1], 0};
  g.h = {(hi[0] - lo[0]) / nx, (hi[1] - lo[1]) / ny, 1};
  g.value.resize(static_cast<size_t>(nx) * ny);
  const double pi = 3.14159265358979323846;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = lo[0] + (i + 0.5) * g.h[0] - centre[0];
      const double y = lo[1] + (j + 0.5) * g.h[1] - centre[1];
      g.value[static_cast<size_t>(j) * nx + i] = gamma / (pi * rc * rc) * std::exp(-(x * x + y * y) / (rc * rc));
    }
  return g;
}

// Taylor-Green cell on [0, L]^2: u = u0 sin(kx) cos(ky), v = -u0 cos(kx) sin(ky), k = 2 pi / L,
// so omega = dv/dx - du/dy = 2 u0 k sin(kx) sin(ky).
ScalarGrid taylor_green_vorticity(int nx, int ny, double length, double u0) {
  ScalarGrid g;
  g.name = "vorticity";
  g.nx = nx;
  g.ny = ny;
  g.h = {length / nx, length / ny, 1};
  g.value.resize(static_cast<size_t>(nx) * ny);
  const double k = 2 * 3.14159265358979323846 / length;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      g.value[static_cast<size_t>(j) * nx + i] = 2 * u0 * k * std::sin(k * (i + 0.5) * g.h[0]) * std::sin(k * (j + 0.5) * g.h[1]);
  return g;
}

}  // namespace silt::render
