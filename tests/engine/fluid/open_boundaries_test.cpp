// Flows through inflow and outflow faces and along free-slip walls: a parabolic inflow develops
// into the discrete Poiseuille parabola downstream, a plug inflow between free-slip walls stays
// uniform (and follows a steered inflow speed), the divergence at round-off in both.
#include <doctest/doctest.h>

#include <cmath>

#include "fluid/module.hpp"
#include "fluid/step.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::fluid;

namespace {

// A 2D channel of length 4 and height 1 between no-slip walls, 64 x 16 cells, nu = 1, from a
// parabolic inflow of peak 1.5 at x = 0 to an outflow at x = 4.
const char* kPoiseuilleInflow =
    "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [4.0, 1.0]\n"
    "[fluid]\ncells = [64, 16]\nviscosity = 1.0\n"
    "[fluid.boundary]\nx_lo = \"inflow\"\nx_lo_velocity = [1.5, 0.0]\nx_lo_profile = \"parabolic\"\n"
    "x_hi = \"outflow\"\n";

// A 3D duct of 2 x 1 x 1, 16 x 8 x 8 cells, free-slip walls on y and z, a plug inflow of speed 1
// at x = 0 and an outflow at x = 2.
const char* kPlugInflow =
    "[scene]\ndimension = 3\n[domain]\nlo = [0.0, 0.0, 0.0]\nhi = [2.0, 1.0, 1.0]\n"
    "[fluid]\ncells = [16, 8, 8]\nviscosity = 0.1\n"
    "[fluid.boundary]\nx_lo = \"inflow\"\nx_lo_velocity = [1.0, 0.0, 0.0]\nx_hi = \"outflow\"\n"
    "y_lo = \"free_slip\"\ny_hi = \"free_slip\"\nz_lo = \"free_slip\"\nz_hi = \"free_slip\"\n";

double largest_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

double largest_diff_from(const std::vector<double>& v, double value) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x - value));
  return m;
}

}  // namespace

TEST_CASE("fluid: a parabolic inflow to an outflow is the discrete Poiseuille parabola downstream") {
  auto sim = test::simulation_from(kPoiseuilleInflow);
  const FluidParams& p = sim->model().params.get<FluidParams>();
  const Grid& g = p.grid;
  const double h = g.h[1];
  // Viscous times H^2 / nu = 1: the slowest transient across the channel decays as exp(-lambda t)
  // with lambda above pi^2 (the gravest diffusion mode between walls), so by t = 4 it is below
  // e^-39, under round-off.
  while (sim->state().t < 4.0) REQUIRE(sim->step());
  const auto& u = sim->state().module_field(fluid_fields().u[0]);
  const auto& v = sim->state().module_field(fluid_fields().u[1]);
  const auto& pr = sim->state().module_field(fluid_fields().p);
  // The developed flow u_j = c (y_j (1 - y_j) + h^2 / 4) solves nu (u_{j+1} - 2 u_j + u_{j-1}) / h^2
  // = -G with the wall ghosts u_{-1} = -u_0 exactly (G = 2 nu c); incompressibility gives it the
  // inflow's flow rate sum_j 1.5 * 4 y_j (1 - y_j), whence c.
  double inflow = 0, shape = 0;
  for (int64_t j = 0; j < 16; ++j) {
    const double y = (j + 0.5) * h;
    inflow += 1.5 * 4 * y * (1 - y);
    shape += y * (1 - y) + h * h / 4;
  }
  const double c = inflow / shape;
  // The inflow's sampled parabola is not that one (it lacks the h^2 / 4): the flow adjusts near
  // the inlet, and the difference decays downstream as exp(-k x / H), k = 8.4 for Stokes flow (the
  // first Papkovich-Fadle eigenvalue; the channel's Reynolds number is 1). From 3e-4 (checked
  // below) at x = H / 2, that is about 1e-13 past x = 3.5 (faces 56 .. 64, the outflow face
  // included); 1e-12 allows for a slower rate, 7.6.
  const auto d = g.face_dims(0);
  double err = 0, near_inlet = 0;
  for (int64_t j = 0; j < d[1]; ++j) {
    const double y = (j + 0.5) * h, exact = c * (y * (1 - y) + h * h / 4);
    for (int64_t i = 56; i < d[0]; ++i) err = std::max(err, std::abs(u[i + d[0] * j] - exact));
    near_inlet = std::max(near_inlet, std::abs(u[8 + d[0] * j] - exact));
  }
  INFO("downstream " << err << ", half a height from the inlet " << near_inlet);
  CHECK(err < 1e-12);
  CHECK(near_inlet > 1e-4);  // the comparison sees a difference where there is one
  CHECK(near_inlet < 1e-3);
  // No cross flow downstream; the pressure falls by G = 2 nu c (rho = 1) per unit length there,
  // and is 0 on the outflow face (its last cells at -G h / 2).
  double v_max = 0;
  for (int64_t j = 1; j < 16; ++j)
    for (int64_t i = 56; i < 64; ++i) v_max = std::max(v_max, std::abs(v[i + 64 * j]));
  CHECK(v_max < 1e-12);
  const double G = 2 * p.nu() * c;
  for (int64_t j = 0; j < 16; ++j) {
    CHECK((pr[62 + 64 * j] - pr[63 + 64 * j]) / h == doctest::Approx(G).epsilon(1e-10));
    CHECK(pr[63 + 64 * j] == doctest::Approx(G * h / 2).epsilon(1e-10));
  }
  // |div u| h / U at round-off.
  sim->state().boundary_seen = true;
  REQUIRE(sim->step());
  CHECK(test::observe(sim->model(), sim->state(), "fluid.div_max") * h / 1.5 < 1e-13);
}

TEST_CASE("fluid: a plug inflow between free-slip walls stays uniform and follows its steered speed") {
  auto sim = test::simulation_from(kPlugInflow);
  const double h = sim->model().params.get<FluidParams>().grid.h[0];
  const FluidFields f = fluid_fields();
  // From rest: the first projection takes the predicted velocity, uniform across the duct, to the
  // divergence-free one, u = 1 everywhere; without friction on the walls nothing changes it after.
  for (int k = 0; k < 10; ++k) REQUIRE(sim->step());
  CHECK(largest_diff_from(sim->state().module_field(f.u[0]), 1.0) < 1e-13);
  CHECK(largest_abs(sim->state().module_field(f.u[1])) < 1e-13);
  CHECK(largest_abs(sim->state().module_field(f.u[2])) < 1e-13);
  CHECK(test::observe(sim->model(), sim->state(), "fluid.div_max") * h < 1e-13);
  CHECK(test::observe(sim->model(), sim->state(), "fluid.cfl") == doctest::Approx(0.5).epsilon(1e-12));
  const double dt_before = sim->state().dt;
  // The inflow steered to 2: the next step's projection carries it through the duct, and the
  // adaptive step halves to hold the target CFL.
  REQUIRE(steer(sim->model_for_steering(), parse_override("fluid.boundary.x_lo_velocity=[2.0, 0.0, 0.0]")) == "");
  REQUIRE(sim->step());
  CHECK(largest_diff_from(sim->state().module_field(f.u[0]), 2.0) < 1e-13);
  CHECK(test::observe(sim->model(), sim->state(), "fluid.bulk_velocity") == doctest::Approx(2.0).epsilon(1e-13));
  REQUIRE(sim->step());
  CHECK(sim->state().dt == doctest::Approx(dt_before / 2).epsilon(1e-12));
  CHECK(test::observe(sim->model(), sim->state(), "fluid.cfl") == doctest::Approx(0.5).epsilon(1e-12));
  CHECK(largest_diff_from(sim->state().module_field(f.u[0]), 2.0) < 1e-13);
  CHECK(test::observe(sim->model(), sim->state(), "fluid.div_max") * h / 2 < 1e-13);
}
