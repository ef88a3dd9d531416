// Two disks pushed together by a constant force in a liquid, through the assembled resistance
// system and its solve: the gap follows the analytic law of the lubrication with a roughness
// cutoff (Peyneau 2009 sec. 1.5.2), exponential above h_min, the linear cutoff's law below it,
// and reaches contact in finite time.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "paste/system.hpp"

using namespace silt;
using namespace silt::paste;

namespace {

// Grain 0 held still (its translation pinned, as the solve pins a cluster's first grain) and
// both rotations held (two grains alone could roll on each other): the velocity of grain 1
// along the line of centres under a force -F along it, at gap h.
double approach_speed(double h, double r, double force, const LubricationLaw& law) {
  Connection c;
  c.i = 0;
  c.j = 1;
  c.n[0] = 1;
  c.r[0] = 2 * r + h;
  c.xi_n = xi_normal(h, r, law);  // R_eq = R for two grains of radius R
  c.xi_t = xi_tangential(h, r, law);
  const SystemLayout l = make_layout(2, 2, nullptr, false);
  ResistanceSystem sys;
  sys.assemble(l, {c}, {r, r}, 0);
  linalg::Vector b = linalg::Vector::Zero(l.size());
  b[3] = -force;  // on grain 1, toward grain 0
  for (const int64_t k : {0, 1, 2, 5}) sys.pin(k, 1.0, b);
  linalg::CholeskyFactor f;
  REQUIRE(f.factorize(sys.matrix()).ok());
  linalg::Vector v(l.size());
  REQUIRE(f.solve(b, v).ok());
  if (v[4] != 0) return std::nan("");  // no sideways motion
  return v[3];
}

}  // namespace

TEST_CASE("two disks under a constant force close their gap by the lubrication law, through the cutoff") {
  const double r = 0.5, force = 2.0, eta = 1.5;
  const LubricationLaw law{eta, 1e-3, 0.25, Cutoff::kLinear};
  const double r_eq = r, c = 1.5 * std::numbers::pi * eta * r_eq * r_eq;
  // The solve gives dh/dt = -F / xi_N(h) at every gap.
  for (double h : {0.2, 1e-2, 1e-3, 5e-4, 1e-5, -1e-3})
    CHECK(approach_speed(h, r, force, law) == doctest::Approx(-force / xi_normal(h, r_eq, law)).epsilon(1e-12));
  // Integrated (RK4 on the solved speed) from h0: above h_min, h = h0 exp(-F t / c); below it,
  // c (2 (h_min - h) / h_min - (h_min^2 - h^2) / (2 h_min^2)) = F (t - t_min); contact at
  // t_min + 1.5 c / F.
  const double h0 = 0.1, hm = law.h_min;
  const double t_min = c / force * std::log(h0 / hm), t_contact = t_min + 1.5 * c / force;
  auto rate = [&](double h) { return approach_speed(h, r, force, law); };
  double h = h0, t = 0;
  const double dt = t_contact / 4000;
  double h_at_t_min = -1;
  while (h > 0 && t < 2 * t_contact) {
    const double k1 = rate(h), k2 = rate(h + 0.5 * dt * k1), k3 = rate(h + 0.5 * dt * k2), k4 = rate(h + dt * k3);
    const double next = h + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    if (h_at_t_min < 0 && t + dt >= t_min) h_at_t_min = h + (t_min - t) / dt * (next - h);
    h = next;
    t += dt;
  }
  CHECK(h_at_t_min == doctest::Approx(hm).epsilon(1e-3));
  // Contact (h = 0) within one step of the analytic time: the smooth law would never get there.
  CHECK(std::abs(t - t_contact) <= dt);
}
