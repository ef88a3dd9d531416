// Values of the fluid at points (line probes): each field interpolated from its own places, the
// vorticity from the cell edges, second order and exact where the discrete field is.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "fluid/module.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::fluid;

namespace {

std::string taylor_green(int dim, int n) {
  const bool d3 = dim == 3;
  const std::string c = std::to_string(n);
  return std::string("[scene]\ndimension = ") + (d3 ? "3" : "2") +
         "\n[domain]\nlo = " + (d3 ? "[0.0, 0.0, 0.0]" : "[0.0, 0.0]") +
         "\nhi = " + (d3 ? "[1.0, 1.0, 1.0]" : "[1.0, 1.0]") +
         "\nperiodic = " + (d3 ? "[true, true, true]" : "[true, true]") + "\n[fluid]\ncells = [" + c + ", " + c +
         (d3 ? ", " + c : "") + "]\nviscosity = 0.01\ninitial = \"taylor_green\"\ndt = 0.001\n";
}

// Largest error of the vorticity probe against the initial Taylor-Green vorticity, over points
// along a line that crosses cells at every fraction (and the box's edges), relative to max |omega|.
double vorticity_probe_error(int dim, int n) {
  auto sim = test::simulation_from(taylor_green(dim, n));
  sim->prepare();
  const FluidParams& p = sim->model().params.get<FluidParams>();
  const double k = 2 * std::numbers::pi;
  double err = 0;
  for (int m = 0; m <= 100; ++m) {
    const double t = m / 100.0;
    const std::array<double, 3> x{t, 0.13 + 0.61 * t, dim == 3 ? 0.9 - 0.7 * t : 0.0};
    const double sx = std::sin(k * x[0]), cx = std::cos(k * x[0]), sy = std::sin(k * x[1]), cy = std::cos(k * x[1]);
    double exact;
    if (dim == 2) {
      exact = 2 * k * sx * sy;  // dv/dx - du/dy of sin cos, -cos sin
    } else {
      const double sz = std::sin(k * x[2]), cz = std::cos(k * x[2]);
      exact = k * std::hypot(cx * sy * sz, sx * cy * sz, 2 * sx * sy * cz);
    }
    err = std::max(err, std::abs(sample(p, sim->state(), "vorticity", x) - exact));
  }
  return err / (2 * k);
}

}  // namespace

TEST_CASE("fluid probes: the vorticity at a point is second order, in 2D and in 3D") {
  // The value of the cell holding the point was off by h |grad omega| (10 % of max |omega| at 32
  // cells); from the edges it is the centred difference's and the interpolation's O(h^2).
  for (int dim : {2, 3}) {
    CAPTURE(dim);
    const int n0 = dim == 2 ? 32 : 16;
    const double coarse = vorticity_probe_error(dim, n0), fine = vorticity_probe_error(dim, 2 * n0);
    INFO("relative errors " << coarse << " " << fine);
    CHECK(coarse < (dim == 2 ? 0.015 : 0.06));  // (k h)^2 / 4: 0.0096 at 32 cells, 0.038 at 16
    CHECK(coarse / fine > 3.5);                 // second order: 4
  }
}

TEST_CASE("fluid probes: across a Poiseuille channel the vorticity is exact, walls and centreline included") {
  // The steady discrete profile is the parabola c (y (1 - y) + h^2 / 4) with wall ghosts -u_0: the
  // edge differences are -u'(y) exactly, at the walls too, and omega = -c (1 - 2 y) is linear.
  auto sim = test::simulation_from(
      "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [0.25, 1.0]\nperiodic = [true, false]\n"
      "[fluid]\ncells = [4, 16]\nviscosity = 1.0\ndt = 1e-3\npressure_gradient = 2.0\n");
  while (sim->state().t < 4.0 - 1e-12) REQUIRE(sim->step());
  const FluidParams& p = sim->model().params.get<FluidParams>();
  const double c = 1.0;  // G / (2 mu)
  double err = 0;
  for (int m = 0; m <= 40; ++m) {
    const double y = m / 40.0;
    err = std::max(err, std::abs(sample(p, sim->state(), "vorticity", {0.07, y, 0}) + c * (1 - 2 * y)));
  }
  CHECK(err < 1e-12);
  CHECK(std::abs(sample(p, sim->state(), "vorticity", {0.2, 0.5, 0})) < 1e-12);
  // The velocity on the walls is the wall's.
  CHECK(std::abs(sample(p, sim->state(), "u", {0.1, 0.0, 0})) < 1e-13);
  CHECK(std::abs(sample(p, sim->state(), "u", {0.1, 1.0, 0})) < 1e-13);
}
